// Neighbour search benchmarks (issue 3): a 3D lattice of spacing dx jittered by +-0.1 dx,
// h = 1.3 dx, cutoff 2h, FP32, in Morton order (ParticleSorter), in cell order
// (ParticleSorter with SortOrder::cell_index) and in a random permutation.
//   BM_CellListBuild      count -> scan -> fill of the cell linked list
//   BM_CellListBuildById  the same list with each cell's particles in ascending id
//                         (CellLinkedList::order_within_cells_by_id: count -> keys -> radix
//                         sort -> scan; in cell order, whose ids ascend here, the host skips
//                         the sort)
//   BM_CellListBuildByIdWithGhosts  the same list on a rank's particles: the owned ones in cell
//                         order (ids ascending), a share of ghosts after them in no order (a
//                         slab of the lattice shuffled); the build sorts only the ghosts' keys
//                         and merges them (merge = 1, the default) or sorts every key (0)
//   BM_StoredListBuild    the stored neighbour lists with their cached pair geometry (one direct
//                         search filling fixed slots per particle; a second one where the
//                         capacity grows, i.e. only at the first build of the Case)
//   BM_DensityPass        one pass of rho_i = m sum_j W(r_ij) (Wendland C2), direct search
//                         or stored lists, through the kernel-shell layer (InteractionDynamics)
//   BM_MortonSort         keys, radix sort and permutation of the sortable variables
//   BM_CellSort           the same by cell index (SortOrder::cell_index) and by (cell index,
//                         id) (SortOrder::cell_index_then_id, the solver's)
// Counters: particles, candidate pairs (particles in the cells walked) and neighbour pairs
// per second, ms per 10^6 particles, and the mean density (1 for this lattice: a check).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/neighbor/pair_counts.hpp"
#include "unisph/neighbor/particle_sorter.hpp"
#include "unisph/particles/body.hpp"

namespace {
using namespace unisph;
using T = float;
constexpr int D = 3;
using Position = Vec<T, D>;

constexpr T dx = 1.0f;
constexpr T h = 1.3f * dx;
constexpr T cutoff = 2.0f * h;

// morton_traversal: the particles in Morton order, visited by the density pass in the cell
// list's order (NeighborSearch::cell_order_source) instead of their index order.
// morton_cell_points: the same, with the cell list keeping a copy of the positions in its own
// order (CellLinkedList::store_positions_in_cell_order; its build then includes the copy).
enum Order { morton = 0, random_order = 1, cell_order = 2, morton_traversal = 3, morton_cell_points = 4 };

// Wendland C2 in 3D, support 2h.
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

class DensitySummation : public InteractionDynamics<DensitySummation> {
 public:
  DensitySummation(InnerRelation<T, D>& relation, DiscreteVariable<T>& density, Index count, bool cell_traversal)
      : relation_(relation), density_(density), count_(count), cell_traversal_(cell_traversal) {}

  struct Kernel {
    NeighborSearch<T, D> search;
    View<T> density;
    WendlandC2 w;
    T mass;
    bool cell_traversal;
    UNISPH_HOST_DEVICE void interaction(Index k, Real) const {
      if (cell_traversal) {
        const CellOrderSource s = search.cell_order_source(k);
        density[s.particle] = mass * sum(s);
      } else {
        density[k] = mass * sum(k);
      }
    }
    template <class Source>
    UNISPH_HOST_DEVICE T sum(Source source) const {
      T total = w(T(0));
      search.for_each_neighbor(source, [&](Index, const NeighborPair<T, D>& pair) { total += w(pair.distance()); });
      return total;
    }
  };
  Kernel make_kernel(KernelContext& context) {
    const T pi = T(3.14159265358979);
    return {relation_.search(context), context.write(density_), WendlandC2{T(1) / h, T(21) / (T(16) * pi * h * h * h)},
            dx * dx * dx, cell_traversal_};
  }
  Index size() const { return count_; }

 private:
  InnerRelation<T, D>& relation_;
  DiscreteVariable<T>& density_;
  Index count_;
  bool cell_traversal_;
};

struct ReadValue {
  View<const T> v;
  UNISPH_HOST_DEVICE double operator()(Index i) const { return double(v[i]); }
};

Box<T, D> lattice_box(int side) {
  return {Position::constant(-0.5f * dx), Position::constant((T(side) - 0.5f) * dx)};
}

// Cells of cutoff / split (split = 1: the default cell size, the 3^3 stencil).
// The smallest such size that still makes split cells reach the cutoff (SearchGrid::reach).
T cell_size_for(int split) {
  T size = cutoff / T(split);
  while (T(split) * size < cutoff) size = std::nextafter(size, cutoff);
  return size;
}

// Positions of the jittered lattice in the requested order, sorted on the grid of the cell
// list that will search them (cached: shared by every policy).
const std::vector<Position>& lattice(int side, Order order, int split) {
  static std::map<std::pair<int, int>, std::vector<Position>> cache;
  auto key = std::make_pair(side, int(order) + 8 * split);
  if (auto it = cache.find(key); it != cache.end()) return it->second;
  const Index n = Index(side) * side * side;
  std::vector<Position> x(n);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<T> jitter(-0.1f * dx, 0.1f * dx);
  for (Index k = 0; k < n; ++k) {
    const Index i = k % side, j = (k / side) % side, l = k / (Index(side) * side);
    x[k] = {{T(i) * dx + jitter(rng), T(j) * dx + jitter(rng), T(l) * dx + jitter(rng)}};
  }
  if (order == random_order) {
    std::shuffle(x.begin(), x.end(), rng);
  } else {
    Body<T, D> body("Lattice", lattice_box(side), n);
    body.positions().assign(x);
    ParticleSorter<T, D> sorter(body.particles(), body.positions(),
                                SearchGrid<T, D>::make(lattice_box(side), cutoff, cell_size_for(split)), 1,
                                order == morton ? SortOrder::morton : SortOrder::cell_index);
    sorter.sort(par);
    x = body.positions().to_vector();
  }
  // Keep only one large set at a time (10^7 positions are 120 MB).
  if (n > 5000000)
    for (auto it = cache.begin(); it != cache.end();)
      it = Index(it->first.first) * it->first.first * it->first.first > 5000000 ? cache.erase(it) : std::next(it);
  return cache.emplace(key, std::move(x)).first->second;
}

int side_for(Index particles) { return int(std::lround(std::cbrt(double(particles)))); }

// Everything one benchmark needs, on one policy.
template <ExecutionPolicy P>
struct Case {
  int side;
  Index n;
  Body<T, D> body;
  CellLinkedList<T, D> cells;
  InnerRelation<T, D> relation;
  DiscreteVariable<T> density;
  DensitySummation summation;
  std::uint64_t candidates = 0;
  std::uint64_t neighbors = 0;

  Case(P policy, Index particles, Order order, SearchMethod method, int split)
      : side(side_for(particles)),
        n(Index(side) * side * side),
        body("Lattice", lattice_box(side), n),
        cells(body.positions(), body.domain(), cutoff, OutsideParticles::clamp, cell_size_for(split)),
        relation(cells, method),
        density("Density", n),
        summation(relation, density, n, order == morton_traversal || order == morton_cell_points) {
    body.positions().assign(lattice(side, order >= morton_traversal ? morton : order, split));
    cells.store_positions_in_cell_order(order == morton_cell_points);
    cells.build(policy);
    const NeighborSearch<T, D> direct = relation.direct_search(policy);
    candidates = particle_reduce(policy, n, Sum<std::uint64_t>{}, CandidateCount<T, D>{direct});
    neighbors = particle_reduce(policy, n, Sum<std::uint64_t>{}, NeighborCount<T, D>{direct});
    relation.update(policy);
    fence(policy);
  }
};

void report(benchmark::State& state, Index n, double candidates, double neighbors) {
  using benchmark::Counter;
  const double it = double(state.iterations());
  state.counters["particles"] = double(n);
  state.counters["particles/s"] = Counter(double(n) * it, Counter::kIsRate);
  state.counters["candidate_pairs/s"] = Counter(candidates * it, Counter::kIsRate);
  state.counters["neighbor_pairs/s"] = Counter(neighbors * it, Counter::kIsRate);
  state.counters["neighbors_per_particle"] = neighbors / double(n);
  // Inverted rate: seconds per (n / 10^9) particles-passes, i.e. ms per pass per 10^6 particles.
  state.counters["ms_per_1e6"] = Counter(double(n) * it / 1e9, Counter::kIsRate | Counter::kInvert);
}

// Device benchmarks skip with the reason where there is no GPU.
template <class P>
bool unavailable(benchmark::State& state) {
  if (P::space == MemorySpace::host || policy_available(PolicyKind::device)) return false;
  state.SkipWithError(("no GPU: " + execution_info().device_unavailable_reason).c_str());
  return true;
}

// Stored lists keep 36 bytes per slot here (j and the FP32 3D NeighborPair), about 3.5 kB per
// particle: 10^7 particles need ~35 GB, more than a small host has (the build machine: 23 GB).
template <class P>
bool too_large_for_host(benchmark::State& state) {
  if (P::space == MemorySpace::device || state.range(0) <= 4000000) return false;
  state.SkipWithError("stored lists of 10^7 particles take ~35 GB: measured on the device only");
  return true;
}

template <class P>
void BM_CellListBuild(benchmark::State& state) {
  const P policy{};
  if (unavailable<P>(state)) return;
  Case<P> c(policy, Index(state.range(0)), Order(state.range(1)), SearchMethod::direct, int(state.range(2)));
  for (auto _ : state) {
    c.cells.build(policy);
    fence(policy);
  }
  report(state, c.n, double(c.candidates), double(c.neighbors));
}

template <class P>
void BM_CellListBuildById(benchmark::State& state) {
  const P policy{};
  if (unavailable<P>(state)) return;
  Case<P> c(policy, Index(state.range(0)), Order(state.range(1)), SearchMethod::direct, int(state.range(2)));
  c.cells.order_within_cells_by_id(c.body.particles());
  for (auto _ : state) {
    c.cells.build(policy);
    fence(policy);
  }
  report(state, c.n, double(c.candidates), double(c.neighbors));
  state.counters["in_cell_order"] = c.cells.report().in_cell_order;
}

template <class P>
void BM_CellListBuildByIdWithGhosts(benchmark::State& state) {
  const P policy{};
  if (unavailable<P>(state)) return;
  const int side = side_for(Index(state.range(0)));
  const Index n = Index(side) * side * side;
  const Index ghosts = Index(state.range(1)) * n / 1000;
  const Index owned = n - ghosts;
  std::vector<std::uint64_t> owned_ids(owned);
  std::iota(owned_ids.begin(), owned_ids.end(), std::uint64_t(0));
  Body<T, D> body("Lattice", lattice_box(side), owned, ghosts, 0, SetShare{std::uint64_t(n), owned_ids});
  // The lattice in cell order; its last `ghosts` particles (the top slab) shuffled as ghosts.
  const std::vector<Position>& x = lattice(side, cell_order, 1);
  std::vector<std::uint64_t> ids(n);
  std::iota(ids.begin(), ids.end(), std::uint64_t(0));
  std::vector<Index> tail(ghosts);
  std::iota(tail.begin(), tail.end(), owned);
  std::shuffle(tail.begin(), tail.end(), std::mt19937_64(7));
  std::vector<Position> x2 = x;
  for (Index k = 0; k < ghosts; ++k) {
    x2[owned + k] = x[tail[k]];
    ids[owned + k] = std::uint64_t(tail[k]);
  }
  body.positions().assign(x2);
  body.particles().ids().assign(ids);
  CellLinkedList<T, D> cells(body.positions(), body.domain(), cutoff, OutsideParticles::clamp, cell_size_for(1));
  cells.order_within_cells_by_id(body.particles());
  cells.sort_only_ghosts(state.range(2) != 0);
  cells.build(policy);
  fence(policy);
  for (auto _ : state) {
    cells.build(policy);
    fence(policy);
  }
  report(state, n, 0, 0);
  state.counters["ghosts"] = double(ghosts);
  state.counters["in_cell_order"] = cells.report().in_cell_order;
}

template <class P>
void BM_StoredListBuild(benchmark::State& state) {
  const P policy{};
  if (unavailable<P>(state) || too_large_for_host<P>(state)) return;
  Case<P> c(policy, Index(state.range(0)), Order(state.range(1)), SearchMethod::stored, int(state.range(2)));
  for (auto _ : state) {
    c.relation.update(policy);
    fence(policy);
  }
  report(state, c.n, double(c.candidates), double(c.neighbors));
}

template <class P, SearchMethod M>
void BM_DensityPass(benchmark::State& state) {
  const P policy{};
  if (unavailable<P>(state) || (M == SearchMethod::stored && too_large_for_host<P>(state))) return;
  Case<P> c(policy, Index(state.range(0)), Order(state.range(1)), M, int(state.range(2)));
  c.summation.exec(policy);  // builds the kernel
  fence(policy);
  for (auto _ : state) {
    c.summation.exec(policy);
    fence(policy);
  }
  report(state, c.n, double(c.candidates), double(c.neighbors));
  state.counters["mean_density"] =
      particle_reduce(policy, c.n, Sum<double>{}, ReadValue{c.density.read(policy)}) / double(c.n);
}

// Keys, radix sort and permutation of the sortable variables, from a random order.
template <class P>
void sort_from_random_order(benchmark::State& state, SortOrder order) {
  const P policy{};
  if (unavailable<P>(state)) return;
  const int side = side_for(Index(state.range(0)));
  const Index n = Index(side) * side * side;
  Body<T, D> body("Lattice", lattice_box(side), n);
  body.particles().add_variable<Vec<T, D>>("Velocity", sortable_variable);
  body.particles().add_variable<T>("Density", sortable_variable);
  ParticleSorter<T, D> sorter(body.particles(), body.positions(), SearchGrid<T, D>::make(lattice_box(side), cutoff), 1,
                              order);
  for (auto _ : state) {
    state.PauseTiming();
    body.positions().assign(lattice(side, random_order, 1));
    body.positions().read(policy);  // the copy to the device is not part of the sort
    fence(policy);
    state.ResumeTiming();
    sorter.sort(policy);
    fence(policy);
  }
  state.counters["particles"] = double(n);
  state.counters["particles/s"] = benchmark::Counter(double(n) * double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["key_bits"] = sorter.key_bits();
}

template <class P>
void BM_MortonSort(benchmark::State& state) {
  sort_from_random_order<P>(state, SortOrder::morton);
}

// From a random order, as BM_MortonSort, by cell index or by (cell index, id).
template <class P, SortOrder O>
void BM_CellSort(benchmark::State& state) {
  sort_from_random_order<P>(state, O);
}

// order: 0 Morton, 1 random, 2 cell order, 3 and 4 Morton visited in cell order (4: with the
// cell-ordered copy of the positions); split: cells of cutoff / split. Host policies:
// 10^6 everywhere, 10^7 on par; the device: 10^6, 4 x 10^6 and 10^7.
template <class P>
void host_sizes(benchmark::internal::Benchmark* b) {
  for (int split : {1, 2})
    for (int order : {morton, random_order, cell_order, morton_cell_points}) {
      b->Args({1000000, order, split});
      if (std::is_same_v<P, ParallelPolicy>) b->Args({10000000, order, split});
    }
  b->ArgNames({"n", "order", "split"})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
}
void device_sizes(benchmark::internal::Benchmark* b) {
  for (int split : {1, 2, 3})
    for (int order : {morton, random_order, cell_order, morton_traversal, morton_cell_points})
      for (int n : {1000000, 4000000, 10000000}) b->Args({n, order, split});
  b->ArgNames({"n", "order", "split"})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.2);
}

// Ghosts per 1000 particles: 50 and 150 (a rank's halo), each merged and sorted whole.
template <class P>
void ghost_sizes(benchmark::internal::Benchmark* b) {
  for (int n : P::space == MemorySpace::device ? std::vector<int>{1000000, 4000000} : std::vector<int>{1000000})
    for (int ghosts : {50, 150})
      for (int merge : {1, 0}) b->Args({n, ghosts, merge});
  b->ArgNames({"n", "ghosts_per_mille", "merge"})->Unit(benchmark::kMillisecond)->UseRealTime();
  if (P::space == MemorySpace::device) b->MinTime(0.2);
  else b->Iterations(3);
}

#define UNISPH_NEIGHBOR_BENCHMARKS(P, SIZES)                                                 \
  BENCHMARK_TEMPLATE(BM_CellListBuild, P)->Apply(SIZES);                                     \
  BENCHMARK_TEMPLATE(BM_CellListBuildById, P)->Apply(SIZES);                                 \
  BENCHMARK_TEMPLATE(BM_CellListBuildByIdWithGhosts, P)->Apply(ghost_sizes<P>);              \
  BENCHMARK_TEMPLATE(BM_DensityPass, P, SearchMethod::direct)->Apply(SIZES);                 \
  BENCHMARK_TEMPLATE(BM_DensityPass, P, SearchMethod::stored)->Apply(SIZES);                 \
  BENCHMARK_TEMPLATE(BM_StoredListBuild, P)->Apply(SIZES);                                   \
  BENCHMARK_TEMPLATE(BM_MortonSort, P)->Arg(1000000)->Arg(10000000)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3); \
  BENCHMARK_TEMPLATE(BM_CellSort, P, SortOrder::cell_index)->Arg(1000000)->Arg(10000000)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3); \
  BENCHMARK_TEMPLATE(BM_CellSort, P, SortOrder::cell_index_then_id)->Arg(1000000)->Arg(10000000)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

UNISPH_NEIGHBOR_BENCHMARKS(SequencedPolicy, host_sizes<SequencedPolicy>)
UNISPH_NEIGHBOR_BENCHMARKS(ParallelPolicy, host_sizes<ParallelPolicy>)
#if UNISPH_HAS_CUDA
UNISPH_NEIGHBOR_BENCHMARKS(ParallelDevicePolicy, device_sizes)
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
