// Periodic boundaries by ghost images (neighbor/periodic_images.hpp): what periodic axes cost
// against closed ones. A 3D lattice of spacing dx jittered by +-0.1 dx in the box
// [-dx/2, (side - 1/2) dx]^3 (so the lattice continues across every face), h = 1.3 dx, cutoff
// 2h, in Morton order (ParticleSorter), with 0, 1 (axis 0) or 3 periodic axes; float and double.
//   BM_ImageBuild     images.build: count -> scan -> total read back -> fill (sources, codes,
//                     image positions)
//   BM_ImageRefresh   images.refresh(policy, density, velocity): the image positions (shifted)
//                     and two variables copied from their sources
//   BM_CellListBuild  the cell list over owned particles and images (box = images.search_box())
//   BM_DensityPass    rho_i = m sum_j W(r_ij) over the owned particles, direct search through
//                     the kernel-shell layer (InteractionDynamics), images found as neighbours
//   BM_Step           what a step adds up to on the neighbour side: wrap, image build, cell-list
//                     build, relation update, refresh, density pass
// Name arguments: n (owned particles, side^3), axes (periodic axes: 0, 1 or 3). The label says
// policy, precision and axes. Counters: particles (owned), ghosts, ghost_fraction, particles/s
// and ms_per_1e6 (per owned particle), neighbour pairs per second and per particle, and the
// mean density. Checks: with all axes periodic there is no surface, so every particle has the
// interior's neighbours (79.2 per particle at 10^6, against 76.9 closed) and the mean density
// is the interior's (1.013 in float at 10^6, against 0.9996 closed, whose faces lack neighbours).
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/neighbor/pair_counts.hpp"
#include "unisph/neighbor/particle_sorter.hpp"
#include "unisph/neighbor/periodic_images.hpp"
#include "unisph/particles/body.hpp"

namespace {
using namespace unisph;
constexpr int D = 3;

template <class T>
struct Scales {
  static constexpr T dx = T(1);
  static constexpr T h = T(1.3) * dx;
  static constexpr T cutoff = T(2) * h;
};

template <class T>
const char* precision() {
  return sizeof(T) == 4 ? "float" : "double";
}

// Wendland C2 in 3D, support 2h.
template <class T>
struct WendlandC2 {
  T inv_h;
  T alpha;  // 21 / (16 pi h^3)
  UNISPH_HOST_DEVICE T operator()(T r) const {
    const T q = r * inv_h;
    if (q >= T(2)) return T(0);
    const T a = T(1) - T(0.5) * q;
    const T a2 = a * a;
    return alpha * a2 * a2 * (T(2) * q + T(1));
  }
};

template <class T>
class DensitySummation : public InteractionDynamics<DensitySummation<T>> {
 public:
  DensitySummation(InnerRelation<T, D>& relation, DiscreteVariable<T>& density, Index owned)
      : relation_(relation), density_(density), owned_(owned) {}

  struct Kernel {
    NeighborSearch<T, D> search;
    View<T> density;
    WendlandC2<T> w;
    T mass;
    UNISPH_HOST_DEVICE void interaction(Index i, Real) const {
      T total = w(T(0));
      search.for_each_neighbor(i, [&](Index, const NeighborPair<T, D>& pair) { total += w(pair.distance()); });
      density[i] = mass * total;
    }
  };
  Kernel make_kernel(KernelContext& context) {
    using S = Scales<T>;
    const T pi = T(3.14159265358979);
    return {relation_.search(context), context.write(density_),
            WendlandC2<T>{T(1) / S::h, T(21) / (T(16) * pi * S::h * S::h * S::h)}, S::dx * S::dx * S::dx};
  }
  // Owned particles only: images are read as neighbours, never updated.
  Index size() const { return owned_; }

 private:
  InnerRelation<T, D>& relation_;
  DiscreteVariable<T>& density_;
  Index owned_;
};

template <class T>
struct ReadValue {
  View<const T> v;
  UNISPH_HOST_DEVICE double operator()(Index i) const { return double(v[i]); }
};

template <class T>
Box<T, D> lattice_box(int side) {
  const T dx = Scales<T>::dx;
  return {Vec<T, D>::constant(T(-0.5) * dx), Vec<T, D>::constant((T(side) - T(0.5)) * dx)};
}

std::array<bool, D> axes_of(int count) {
  std::array<bool, D> a{};
  for (int k = 0; k < count && k < D; ++k) a[k] = true;
  return a;
}

// The jittered lattice in Morton order (cached per size and precision: shared by every policy).
template <class T>
const std::vector<Vec<T, D>>& lattice(int side) {
  static std::map<int, std::vector<Vec<T, D>>> cache;
  if (auto it = cache.find(side); it != cache.end()) return it->second;
  const Index n = Index(side) * side * side;
  const T dx = Scales<T>::dx;
  std::vector<Vec<T, D>> x(n);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> jitter(-0.1 * dx, 0.1 * dx);
  for (Index k = 0; k < n; ++k) {
    const Index i = k % side, j = (k / side) % side, l = k / (Index(side) * side);
    x[k] = {{T(T(i) * dx + jitter(rng)), T(T(j) * dx + jitter(rng)), T(T(l) * dx + jitter(rng))}};
  }
  Body<T, D> body("Lattice", lattice_box<T>(side), n);
  body.positions().assign(x);
  ParticleSorter<T, D> sorter(body.particles(), body.positions(),
                              SearchGrid<T, D>::make(lattice_box<T>(side), Scales<T>::cutoff), 1, SortOrder::morton);
  sorter.sort(par);
  return cache.emplace(side, body.positions().to_vector()).first->second;
}

int side_for(Index particles) { return int(std::lround(std::cbrt(double(particles)))); }

// Everything one benchmark needs, on one policy, built once (images, cells, relation).
template <ExecutionPolicy P, class T>
struct Case {
  int side;
  Index n;
  int axes;
  Body<T, D> body;
  DiscreteVariable<T>& density;
  DiscreteVariable<Vec<T, D>>& velocity;
  PeriodicImages<T, D> images;
  CellLinkedList<T, D> cells;
  InnerRelation<T, D> relation;
  DensitySummation<T> summation;
  std::uint64_t neighbors = 0;

  Case(P policy, Index particles, int periodic_axes)
      : side(side_for(particles)),
        n(Index(side) * side * side),
        axes(periodic_axes),
        body("Lattice", lattice_box<T>(side), n),
        density(body.particles().template add_variable<T>("Density")),
        velocity(body.particles().template add_variable<Vec<T, D>>("Velocity")),
        images(body.particles(), body.positions(), lattice_box<T>(side), axes_of(periodic_axes), Scales<T>::cutoff),
        cells(body.positions(), images.search_box(), Scales<T>::cutoff),
        relation(cells, SearchMethod::direct),
        summation(relation, density, n) {
    body.positions().assign(lattice<T>(side));
    images.build(policy);
    images.refresh(policy, density, velocity);
    cells.build(policy);
    relation.set_source_count(n);
    relation.update(policy);
    neighbors = particle_reduce(policy, n, Sum<std::uint64_t>{}, NeighborCount<T, D>{relation.direct_search(policy)});
    fence(policy);
  }

  void label(benchmark::State& state) const {
    state.SetLabel("policy=" + std::string(P::name) + " precision=" + precision<T>() +
                   " periodic_axes=" + std::to_string(axes));
  }
};

template <class P, class T>
void report(benchmark::State& state, const Case<P, T>& c) {
  using benchmark::Counter;
  const double it = double(state.iterations());
  const double ghosts = double(c.images.ghost_count());
  state.counters["particles"] = double(c.n);
  state.counters["ghosts"] = ghosts;
  state.counters["ghost_fraction"] = ghosts / double(c.n);
  state.counters["particles/s"] = Counter(double(c.n) * it, Counter::kIsRate);
  state.counters["neighbor_pairs/s"] = Counter(double(c.neighbors) * it, Counter::kIsRate);
  state.counters["neighbors_per_particle"] = double(c.neighbors) / double(c.n);
  // Inverted rate: ms per pass per 10^6 owned particles.
  state.counters["ms_per_1e6"] = Counter(double(c.n) * it / 1e9, Counter::kIsRate | Counter::kInvert);
  c.label(state);
}

template <class P>
bool unavailable(benchmark::State& state) {
  if (P::space == MemorySpace::host || policy_available(PolicyKind::device)) return false;
  state.SkipWithError(("no GPU: " + execution_info().device_unavailable_reason).c_str());
  return true;
}

template <class P, class T>
void BM_ImageBuild(benchmark::State& state) {
  const P policy{};
  if (unavailable<P>(state)) return;
  Case<P, T> c(policy, Index(state.range(0)), int(state.range(1)));
  for (auto _ : state) {
    c.images.build(policy);
    fence(policy);
  }
  report(state, c);
}

template <class P, class T>
void BM_ImageRefresh(benchmark::State& state) {
  const P policy{};
  if (unavailable<P>(state)) return;
  Case<P, T> c(policy, Index(state.range(0)), int(state.range(1)));
  for (auto _ : state) {
    c.images.refresh(policy, c.density, c.velocity);
    fence(policy);
  }
  report(state, c);
}

template <class P, class T>
void BM_CellListBuild(benchmark::State& state) {
  const P policy{};
  if (unavailable<P>(state)) return;
  Case<P, T> c(policy, Index(state.range(0)), int(state.range(1)));
  for (auto _ : state) {
    c.cells.build(policy);
    fence(policy);
  }
  report(state, c);
}

template <class P, class T>
void BM_DensityPass(benchmark::State& state) {
  const P policy{};
  if (unavailable<P>(state)) return;
  Case<P, T> c(policy, Index(state.range(0)), int(state.range(1)));
  c.summation.exec(policy);  // builds the kernel
  fence(policy);
  for (auto _ : state) {
    c.summation.exec(policy);
    fence(policy);
  }
  report(state, c);
  state.counters["mean_density"] =
      particle_reduce(policy, c.n, Sum<double>{}, ReadValue<T>{c.density.read(policy)}) / double(c.n);
}

template <class P, class T>
void BM_Step(benchmark::State& state) {
  const P policy{};
  if (unavailable<P>(state)) return;
  Case<P, T> c(policy, Index(state.range(0)), int(state.range(1)));
  c.summation.exec(policy);
  fence(policy);
  for (auto _ : state) {
    c.images.wrap(policy);
    c.images.build(policy);
    c.cells.build(policy);
    c.relation.update(policy);
    c.images.refresh(policy, c.density, c.velocity);
    c.summation.exec(policy);
    fence(policy);
  }
  report(state, c);
}

// axes: 0 closed, 1 periodic along axis 0, 3 periodic along every axis. Host: 10^6 (the
// 2-core build machine); device: 10^6 and 4 x 10^6.
void host_sizes(benchmark::internal::Benchmark* b) {
  for (int axes : {0, 1, 3}) b->Args({1000000, axes});
  b->ArgNames({"n", "axes"})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
}
void device_sizes(benchmark::internal::Benchmark* b) {
  for (int n : {1000000, 4000000})
    for (int axes : {0, 1, 3}) b->Args({n, axes});
  b->ArgNames({"n", "axes"})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.2);
}

#define UNISPH_PERIODIC_BENCHMARKS(P, T, SIZES)             \
  BENCHMARK_TEMPLATE(BM_ImageBuild, P, T)->Apply(SIZES);    \
  BENCHMARK_TEMPLATE(BM_ImageRefresh, P, T)->Apply(SIZES);  \
  BENCHMARK_TEMPLATE(BM_CellListBuild, P, T)->Apply(SIZES); \
  BENCHMARK_TEMPLATE(BM_DensityPass, P, T)->Apply(SIZES);   \
  BENCHMARK_TEMPLATE(BM_Step, P, T)->Apply(SIZES);

UNISPH_PERIODIC_BENCHMARKS(SequencedPolicy, float, host_sizes)
UNISPH_PERIODIC_BENCHMARKS(ParallelPolicy, float, host_sizes)
UNISPH_PERIODIC_BENCHMARKS(ParallelPolicy, double, host_sizes)
#if UNISPH_HAS_CUDA
UNISPH_PERIODIC_BENCHMARKS(ParallelDevicePolicy, float, device_sizes)
UNISPH_PERIODIC_BENCHMARKS(ParallelDevicePolicy, double, device_sizes)
#endif

}  // namespace

// Device benchmarks skip (with the reason) where no GPU is present.
int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  if (!policy_available(PolicyKind::device))
    benchmark::AddCustomContext("device", "absent: " + execution_info().device_unavailable_reason);
  else
    benchmark::AddCustomContext("device", execution_info().device_name);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
