// Periodic boundaries by ghost images (neighbor/periodic_images.hpp) and by wrapped cell indices
// (neighbor/periodic_cell_list.hpp, periodic_cell_walk.hpp): what periodic axes cost against
// closed ones, and which of the two ways is faster (issue 21). A 3D lattice of spacing dx jittered by +-0.1 dx in the box
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
// The same through wrapped cell indices (no images: the cell list holds the owned particles on a
// grid that divides the periodic axes exactly, the walk shifts the ranges that cross a face):
//   BM_WrappedCellListBuild   the cell list (PeriodicCellList::build)
//   BM_WrappedDensityPass     the density pass through PeriodicCellWalk (InteractionDynamics)
//   BM_WrappedStep            wrap, cell-list build, density pass
// and, to tell the walk's cost from its grid's: cells that divide L are wider than the cutoff
// (100 / floor(100 / 2.6) = 2.63 dx at 10^6), so the wrapped walk has more candidates; on this
// jittered lattice the host's density pass costs far more than that (about +50 % with cells of
// 2.63 dx, whichever method). BM_DensityPassWideCells is BM_DensityPass with the images' cell
// list on cells of that width along every axis.
// Name arguments: n (owned particles, side^3), axes (periodic axes: 0, 1 or 3). The label says
// policy, precision, axes and method (images, wrapped). Counters: particles (owned), ghosts,
// ghost_fraction, particles/s and ms_per_1e6 (per owned particle), neighbour pairs per second and
// per particle, candidates per particle (the particles of the walked cells), and the mean
// density. Both methods find the same pairs: the same neighbours per particle, and mean densities
// equal to round-off (the sums run in another order, and a pair across a face computes
// (x_i - L) - x_j instead of x_i - (x_j + L)). Checks: with all axes periodic there is no surface, so every particle has the
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
#include "unisph/neighbor/periodic_cell_list.hpp"
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

// The kernel-side search of each method: NeighborSearch through the relation (images), the
// PeriodicCellWalk of the wrapped cell list.
template <class T>
NeighborSearch<T, D> search_of(InnerRelation<T, D>& relation, KernelContext& context) {
  return relation.search(context);
}
template <class T>
PeriodicCellWalk<T, D> search_of(PeriodicCellList<T, D>& cells, KernelContext& context) {
  return cells.inner_walk(context);
}

template <class T, class Neighbors>
class DensitySummation : public InteractionDynamics<DensitySummation<T, Neighbors>> {
 public:
  using Search = decltype(search_of(std::declval<Neighbors&>(), std::declval<KernelContext&>()));
  DensitySummation(Neighbors& relation, DiscreteVariable<T>& density, Index owned)
      : relation_(relation), density_(density), owned_(owned) {}

  struct Kernel {
    Search search;
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
    return {search_of(relation_, context), context.write(density_),
            WendlandC2<T>{T(1) / S::h, T(21) / (T(16) * pi * S::h * S::h * S::h)}, S::dx * S::dx * S::dx};
  }
  // Owned particles only: images are read as neighbours, never updated.
  Index size() const { return owned_; }

 private:
  Neighbors& relation_;
  DiscreteVariable<T>& density_;
  Index owned_;
};

// Candidate and neighbour counts of the wrapped walk (pair_counts.hpp has NeighborSearch's).
template <class T>
struct WalkCandidateCount {
  PeriodicCellWalk<T, D> walk;
  UNISPH_HOST_DEVICE std::uint64_t operator()(Index i) const { return walk.candidate_count(i); }
};
template <class T>
struct WalkNeighborCount {
  PeriodicCellWalk<T, D> walk;
  UNISPH_HOST_DEVICE std::uint64_t operator()(Index i) const {
    std::uint64_t n = 0;
    walk.for_each_neighbor(i, [&](Index, const NeighborPair<T, D>&) { ++n; });
    return n;
  }
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
  DensitySummation<T, InnerRelation<T, D>> summation;
  std::uint64_t neighbors = 0;
  std::uint64_t candidates = 0;

  Case(P policy, Index particles, int periodic_axes, T cell_size = T(0))
      : side(side_for(particles)),
        n(Index(side) * side * side),
        axes(periodic_axes),
        body("Lattice", lattice_box<T>(side), n),
        density(body.particles().template add_variable<T>("Density")),
        velocity(body.particles().template add_variable<Vec<T, D>>("Velocity")),
        images(body.particles(), body.positions(), lattice_box<T>(side), axes_of(periodic_axes), Scales<T>::cutoff),
        cells(body.positions(), images.search_box(), Scales<T>::cutoff, OutsideParticles::clamp, cell_size),
        relation(cells, SearchMethod::direct),
        summation(relation, density, n) {
    body.positions().assign(lattice<T>(side));
    images.build(policy);
    images.refresh(policy, density, velocity);
    cells.build(policy);
    relation.set_source_count(n);
    relation.update(policy);
    neighbors = particle_reduce(policy, n, Sum<std::uint64_t>{}, NeighborCount<T, D>{relation.direct_search(policy)});
    candidates =
        particle_reduce(policy, n, Sum<std::uint64_t>{}, CandidateCount<T, D>{relation.direct_search(policy)});
    fence(policy);
  }

  Index ghosts() const { return images.ghost_count(); }
  void label(benchmark::State& state) const {
    state.SetLabel("policy=" + std::string(P::name) + " precision=" + precision<T>() +
                   " periodic_axes=" + std::to_string(axes) + " method=images");
  }
};

// The same lattice through wrapped cell indices: no images, one cell list on the divided grid.
template <ExecutionPolicy P, class T>
struct WrappedCase {
  int side;
  Index n;
  int axes;
  Body<T, D> body;
  DiscreteVariable<T>& density;
  DiscreteVariable<Vec<T, D>>& velocity;
  PeriodicCellList<T, D> cells;
  DensitySummation<T, PeriodicCellList<T, D>> summation;
  std::uint64_t neighbors = 0;
  std::uint64_t candidates = 0;

  WrappedCase(P policy, Index particles, int periodic_axes)
      : side(side_for(particles)),
        n(Index(side) * side * side),
        axes(periodic_axes),
        body("Lattice", lattice_box<T>(side), n),
        density(body.particles().template add_variable<T>("Density")),
        velocity(body.particles().template add_variable<Vec<T, D>>("Velocity")),
        cells(body.positions(), lattice_box<T>(side), axes_of(periodic_axes), Scales<T>::cutoff),
        summation(cells, density, n) {
    body.positions().assign(lattice<T>(side));
    cells.wrap(policy);
    cells.build(policy);
    neighbors = particle_reduce(policy, n, Sum<std::uint64_t>{}, WalkNeighborCount<T>{cells.inner_walk(policy)});
    candidates = particle_reduce(policy, n, Sum<std::uint64_t>{}, WalkCandidateCount<T>{cells.inner_walk(policy)});
    fence(policy);
  }

  Index ghosts() const { return 0; }
  void label(benchmark::State& state) const {
    state.SetLabel("policy=" + std::string(P::name) + " precision=" + precision<T>() +
                   " periodic_axes=" + std::to_string(axes) + " method=wrapped");
  }
};

template <class C>
void report(benchmark::State& state, const C& c) {
  using benchmark::Counter;
  const double it = double(state.iterations());
  const double ghosts = double(c.ghosts());
  state.counters["particles"] = double(c.n);
  state.counters["ghosts"] = ghosts;
  state.counters["ghost_fraction"] = ghosts / double(c.n);
  state.counters["particles/s"] = Counter(double(c.n) * it, Counter::kIsRate);
  state.counters["neighbor_pairs/s"] = Counter(double(c.neighbors) * it, Counter::kIsRate);
  state.counters["neighbors_per_particle"] = double(c.neighbors) / double(c.n);
  state.counters["candidates_per_particle"] = double(c.candidates) / double(c.n);
  // Inverted rate: ms per pass per 10^6 owned particles.
  state.counters["ms_per_1e6"] = Counter(double(c.n) * it / 1e9, Counter::kIsRate | Counter::kInvert);
  c.label(state);
}

// The mean density of the owned particles.
template <class P, class T>
double mean_density(P policy, DiscreteVariable<T>& density, Index n) {
  return particle_reduce(policy, n, Sum<double>{}, ReadValue<T>{density.read(policy)}) / double(n);
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
  state.counters["mean_density"] = mean_density(policy, c.density, c.n);
  state.counters["cell_size"] = double(c.cells.grid().cell_size);
}

// The cells of a wrapped grid of the lattice box with every axis periodic (L / floor(L / cutoff)).
template <class T>
T wrapped_cell_width(int side) {
  std::array<bool, D> all;
  all.fill(true);
  return SearchGrid<T, D>::make_periodic(lattice_box<T>(side), Scales<T>::cutoff, all).axis_cell_size[0];
}

template <class P, class T>
void BM_DensityPassWideCells(benchmark::State& state) {
  const P policy{};
  if (unavailable<P>(state)) return;
  const Index n = Index(state.range(0));
  Case<P, T> c(policy, n, int(state.range(1)), wrapped_cell_width<T>(side_for(n)));
  c.summation.exec(policy);
  fence(policy);
  for (auto _ : state) {
    c.summation.exec(policy);
    fence(policy);
  }
  report(state, c);
  state.counters["mean_density"] = mean_density(policy, c.density, c.n);
  state.counters["cell_size"] = double(c.cells.grid().cell_size);
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
  report(state, c);  state.counters["mean_density"] = mean_density(policy, c.density, c.n);
}

template <class P, class T>
void BM_WrappedCellListBuild(benchmark::State& state) {
  const P policy{};
  if (unavailable<P>(state)) return;
  WrappedCase<P, T> c(policy, Index(state.range(0)), int(state.range(1)));
  for (auto _ : state) {
    c.cells.build(policy);
    fence(policy);
  }
  report(state, c);
}

template <class P, class T>
void BM_WrappedDensityPass(benchmark::State& state) {
  const P policy{};
  if (unavailable<P>(state)) return;
  WrappedCase<P, T> c(policy, Index(state.range(0)), int(state.range(1)));
  c.summation.exec(policy);  // builds the kernel
  fence(policy);
  for (auto _ : state) {
    c.summation.exec(policy);
    fence(policy);
  }
  report(state, c);
  state.counters["mean_density"] = mean_density(policy, c.density, c.n);
  state.counters["cell_size"] = double(c.cells.grid().axis_cell_size[0]);
}

template <class P, class T>
void BM_WrappedStep(benchmark::State& state) {
  const P policy{};
  if (unavailable<P>(state)) return;
  WrappedCase<P, T> c(policy, Index(state.range(0)), int(state.range(1)));
  c.summation.exec(policy);
  fence(policy);
  for (auto _ : state) {
    c.cells.wrap(policy);
    c.cells.build(policy);
    c.summation.exec(policy);
    fence(policy);
  }
  report(state, c);
  state.counters["mean_density"] = mean_density(policy, c.density, c.n);
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

#define UNISPH_PERIODIC_BENCHMARKS(P, T, SIZES)                    \
  BENCHMARK_TEMPLATE(BM_ImageBuild, P, T)->Apply(SIZES);           \
  BENCHMARK_TEMPLATE(BM_ImageRefresh, P, T)->Apply(SIZES);         \
  BENCHMARK_TEMPLATE(BM_CellListBuild, P, T)->Apply(SIZES);        \
  BENCHMARK_TEMPLATE(BM_DensityPass, P, T)->Apply(SIZES);          \
  BENCHMARK_TEMPLATE(BM_Step, P, T)->Apply(SIZES);                 \
  BENCHMARK_TEMPLATE(BM_DensityPassWideCells, P, T)->Apply(SIZES); \
  BENCHMARK_TEMPLATE(BM_WrappedCellListBuild, P, T)->Apply(SIZES); \
  BENCHMARK_TEMPLATE(BM_WrappedDensityPass, P, T)->Apply(SIZES);   \
  BENCHMARK_TEMPLATE(BM_WrappedStep, P, T)->Apply(SIZES);

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
