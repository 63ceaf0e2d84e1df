// Hierarchical views (iter::View) against hand-written loops over the same supercells:
//   all_particles   every particle of every supercell
//   strided         every second frame of each supercell, and in it the slots 1, 4, 7, ...
//   neighbors_*     neighbour iteration over a cell linked list (issue 8 (c)): for every particle
//                   of a jittered 3D lattice (h = 1.3 dx, cutoff 2h, cells of the cutoff, FP32),
//                   sum W(r) over its neighbours; particles in cell order (neighbors_cell_order)
//                   or in a random order (neighbors_any_order). Loops: "for_each" is
//                   iter::for_each_neighbor (a view of the 3^3 cells around the particle's cell,
//                   child view: the particles of each cell), "view" the same views walked by the
//                   iterator loop, "hand" the plain loop over the 3^3 cells and their CSR ranges,
//                   "direct" NeighborSearch::for_each_direct_neighbor (the engine's search, which
//                   walks one CSR range per row of 3 cells). Same pairs in the same order: the
//                   checksum (sum of the per-particle sums) is equal bit for bit.
//   packages        a loop over every data point of a sparse grid (48^3 cells, all with a package):
//                   out = 2 in + local point. "hand" is the flat loop data_point_for was before it
//                   walked views (one particle_for item per data point, package and local point
//                   from the item's index; kept here as the reference), "engine" the engine's
//                   data_point_for (grid/package_for.hpp: a view of packages -> data points, one
//                   worker per package on the host, a team of 64 threads per package, 4 teams per
//                   CUDA block, on the GPU), "for_each"/"view" a view of one package per item with
//                   its child view of the 4^3 values, "plain" one item per package with a plain
//                   loop, "team" (GPU) one CUDA block of 64 per package (collective_for).
// Loops: "view" is the slides' iterator loop (a range-for over the view), "for_each" the
// view's internal iteration (View::for_each: one plain loop per level), "nested" a range-for per
// level over View::children() (a range of the child views), "hand" the loop one
// writes without views. Each sums x * w over the particles it visits. Both loops of a pair must produce the same
// checksum (the values are small integers, so the sums are exact in any order); the checksum is
// reported as a counter.
//
//   <case>/<loop>/<policy>   policy seq, par: one supercell per item of particle_for (oneTBB shares
//                            the supercells among the cores); device: the same on the GPU, one
//                            thread per supercell; each item stores its supercell's sum
//   <case>/<loop>/team       GPU: one block of 256 threads per supercell, the particles of each frame
//                            shared through the block (collective_for, collectivity::DeviceBlock);
//                            each thread stores its partial sum
// The checksum (the sum of the stored sums) is added up on the host after the timed loop.
//
// scripts/views_bench_report.py turns --benchmark_format=json output (with
// --benchmark_repetitions=20) into the table of medians and ratios in docs/views.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "unisph/grid/package_for.hpp"
#include "unisph/grid/package_mesh.hpp"
#include "unisph/iter/iter.hpp"
#include "unisph/neighbor/neighbor_views.hpp"
#include "unisph/grid/package_traits.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/unisph.hpp"

namespace {
using namespace unisph;
using iter::all;
using iter::RuntimeTuple;
namespace direction = iter::direction;
namespace collectivity = iter::collectivity;

struct BenchParticle {
  double x, w;
};
constexpr Index slots = 256;
using BenchFrame = iter::Frame<BenchParticle, slots>;
using ConstFrame = const BenchFrame;
using Cells = iter::Supercells<ConstFrame>;
constexpr Index supercell_count = 8192;

// 8192 supercells of 200..1799 particles (about 8.2 million, 131 MB), frames of a supercell
// adjacent in the pool, as after a sort.
iter::SupercellContainer<BenchParticle, slots>& supercells() {
  static iter::SupercellContainer<BenchParticle, slots> container("bench", supercell_count);
  static bool filled = false;
  if (!filled) {
    std::uint64_t state = 12345, id = 0;
    std::vector<BenchParticle> particles;
    for (Index c = 0; c < supercell_count; ++c) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      const Index n = 200 + (state >> 33) % 1600;
      particles.clear();
      for (Index p = 0; p < n; ++p, ++id) particles.push_back({double(id % 1000), double(id % 7 + 1)});
      container.append(c, particles);
    }
    filled = true;
  }
  return container;
}

// The body of every loop: adds x * w of a valid slot.
struct Accumulate {
  double& sum;
  UNISPH_HOST_DEVICE void operator()(iter::SlotRef<const BenchParticle> slot) const {
    if (slot) sum += slot->x * slot->w;
  }
};

// The view loops come in three forms: the slides' iterator loop (a range-for), View::for_each,
// and the range of child ranges (View::children(): one range-for per level).
enum Form { iterator_loop = 0, for_each_loop = 1, nested_loop = 2 };
template <int F, class View>
UNISPH_HOST_DEVICE double sum_over(const View& view) {
  double sum = 0;
  const Accumulate add{sum};
  if constexpr (F == for_each_loop)
    view.for_each(add);
  else if constexpr (F == nested_loop)
    for (auto frame : view.children())
      for (auto slot : frame) add(slot);
  else
    for (auto slot : view) add(slot);
  return sum;
}

// ---- (a) all particles ------------------------------------------------------------------------

template <int F>
struct AllView {
  Cells cells;
  UNISPH_HOST_DEVICE double operator()(Index c) const {
    using Particles = iter::View<ConstFrame, direction::Forward, collectivity::None, iter::CompileTimeTuple<>>;
    const iter::View<iter::Supercell<ConstFrame>, direction::Forward, collectivity::None, iter::CompileTimeTuple<>, Particles>
        view(cells[c]);
    return sum_over<F>(view);
  }
};

struct AllHand {
  Cells cells;
  UNISPH_HOST_DEVICE double operator()(Index c) const {
    const iter::SupercellHeader h = cells.headers[c];
    double sum = 0;
    for (Index f = h.first_frame; f != iter::no_frame; f = cells.frames[f].next) {
      const Index n = f == h.last_frame ? h.particles_in_last_frame : slots;
      const BenchParticle* p = cells.frames[f].slots;
      for (Index s = 0; s < n; ++s) sum += p[s].x * p[s].w;
    }
    return sum;
  }
};

// ---- (b) a strided subset: every second frame, slots 1, 4, 7, ... -------------------------------

constexpr Index frame_jump = 2, slot_offset = 1, slot_jump = 3;

template <int F>
struct StridedView {
  Cells cells;
  UNISPH_HOST_DEVICE double operator()(Index c) const {
    using Particles = iter::View<ConstFrame, direction::Forward, collectivity::None, RuntimeTuple>;
    const iter::View<iter::Supercell<ConstFrame>, direction::Forward, collectivity::None, RuntimeTuple, Particles> view(
        cells[c], RuntimeTuple{0, all, frame_jump}, Particles(nullptr, RuntimeTuple{slot_offset, all, slot_jump}));
    return sum_over<F>(view);
  }
};

struct StridedHand {
  Cells cells;
  UNISPH_HOST_DEVICE double operator()(Index c) const {
    const iter::SupercellHeader h = cells.headers[c];
    double sum = 0;
    Index k = 0;
    for (Index f = h.first_frame; f != iter::no_frame; f = cells.frames[f].next, ++k) {
      if (k % frame_jump != 0) continue;
      const Index n = f == h.last_frame ? h.particles_in_last_frame : slots;
      const BenchParticle* p = cells.frames[f].slots;
      for (Index s = slot_offset; s < n; s += slot_jump) sum += p[s].x * p[s].w;
    }
    return sum;
  }
};

// ---- the same per team (GPU blocks of 256 threads) --------------------------------------------

constexpr Index team_size = 256;

template <bool Strided, int F>
struct TeamView {
  Cells cells;
  unisph::View<double> partial;  // team_size per supercell
  template <class Team>
  UNISPH_HOST_DEVICE void operator()(const Team& team, Index c) const {
    using Particles = iter::View<ConstFrame, direction::Forward, Team, RuntimeTuple>;
    const RuntimeTuple frames{0, all, Strided ? frame_jump : 1};
    const RuntimeTuple particles{Strided ? slot_offset : 0, all, Strided ? slot_jump : 1};
    const iter::View<iter::Supercell<ConstFrame>, direction::Forward, collectivity::None, RuntimeTuple, Particles> view(
        cells[c], frames, Particles(nullptr, particles, iter::NoChild{}, team));
    partial[c * team_size + team.rank()] = sum_over<F>(view);
  }
};

template <bool Strided>
struct TeamHand {
  Cells cells;
  unisph::View<double> partial;
  template <class Team>
  UNISPH_HOST_DEVICE void operator()(const Team& team, Index c) const {
    const iter::SupercellHeader h = cells.headers[c];
    const Index first_slot = (Strided ? slot_offset : 0) + team.rank() * (Strided ? slot_jump : 1);
    const Index step = team.size() * (Strided ? slot_jump : 1);
    double sum = 0;
    Index k = 0;
    for (Index f = h.first_frame; f != iter::no_frame; f = cells.frames[f].next, ++k) {
      if (Strided && k % frame_jump != 0) continue;
      const Index n = f == h.last_frame ? h.particles_in_last_frame : slots;
      const BenchParticle* p = cells.frames[f].slots;
      for (Index s = first_slot; s < n; s += step) sum += p[s].x * p[s].w;
    }
    partial[c * team_size + team.rank()] = sum;
  }
};

template <class P>
bool skip_unavailable(benchmark::State& state) {
  if (P::space == MemorySpace::device && !policy_available(PolicyKind::device)) {
    state.SkipWithError(execution_info().device_unavailable_reason.c_str());
    return true;
  }
  return false;
}

// One supercell per item of particle_for; each item stores its supercell's sum. The checksum is
// added up on the host after the timed loop, the same way for every policy.
template <class Kernel>
struct StoreSum {
  Kernel loop;
  unisph::View<double> sums;
  UNISPH_HOST_DEVICE void operator()(Index c) const { sums[c] = loop(c); }
};

double host_total(DiscreteVariable<double>& values) {
  double total = 0;
  for (double v : values.to_vector()) total += v;
  return total;
}

template <class P, class Kernel>
void PerSupercell(benchmark::State& state) {
  if (skip_unavailable<P>(state)) return;
  DiscreteVariable<double> sums("sums", supercell_count);
  const StoreSum<Kernel> kernel{Kernel{supercells().read(P{})}, sums.write(P{})};
  particle_for(P{}, supercell_count, kernel);  // warm-up
  fence(P{});
  for (auto _ : state) {
    particle_for(P{}, supercell_count, kernel);
    fence(P{});
  }
  state.counters["checksum"] = host_total(sums);
  state.counters["frames"] = double(supercells().frame_count());
  state.SetLabel("policy=" + std::string(P::name));
}

template <class Kernel>
void PerTeam(benchmark::State& state) {
  using P = ParallelDevicePolicy;
  if (skip_unavailable<P>(state)) return;
  DiscreteVariable<double> partial("partial", supercell_count * team_size);
  const Kernel kernel{supercells().read(P{}), partial.write(P{})};
  iter::collective_for(P{}, supercell_count, team_size, kernel);  // warm-up
  fence(P{});
  for (auto _ : state) {
    iter::collective_for(P{}, supercell_count, team_size, kernel);
    fence(P{});
  }
  state.counters["checksum"] = host_total(partial);
  state.SetLabel("policy=device, one block of 256 per supercell");
}

// ---- (c) neighbour iteration over the cell linked list ----------------------------------------

namespace nb {
using T = float;
constexpr int D = 3;
using Position = Vec<T, D>;
constexpr T dx = 1.0f, h = 1.3f * dx, cutoff = 2.0f * h;
constexpr int side = 30;  // 27000 particles, about 73 neighbours and 470 candidates each

// Wendland C2 in 3D, support 2h.
struct WendlandC2 {
  UNISPH_HOST_DEVICE T operator()(T r) const {
    const T q = r * (T(1) / h);
    if (q >= T(2)) return T(0);
    const T a = T(1) - T(0.5) * q;
    const T a2 = a * a;
    return T(21) / (T(16) * T(3.14159265358979) * h * h * h) * a2 * a2 * (T(2) * q + T(1));
  }
};

enum Loop { by_for_each, by_iterators, by_hand, by_direct_search };

// The plain loop: the 3^3 cells around i's cell (clipped to the grid), in linear order, and the
// CSR places of each.
template <class F>
UNISPH_HOST_DEVICE void hand_neighbors(const NeighborSearch<T, D>& s, Index i, F& f) {
  const Position xi = s.sources[i];
  const SearchGrid<T, D>& grid = s.targets.grid;
  const CellPlacement<D> at = grid.place(xi);
  if (at.status & placement_non_finite) return;
  if (s.inner && s.targets.flag_outside && at.status != placement_inside) return;
  int lo[D], hi[D];
  for (int a = 0; a < D; ++a) {
    lo[a] = at.cell[a] > 0 ? at.cell[a] - 1 : 0;
    hi[a] = at.cell[a] + 1 < grid.cells[a] ? at.cell[a] + 1 : grid.cells[a] - 1;
  }
  const bool ordered = s.targets.in_cell_order();
  const auto visit = [&](Index j) {
    if (s.inner && j == i) return;
    NeighborPair<T, D> pair;
    if (grid.test_pair(xi, s.targets.positions[j], pair.r_ij, pair.squared_distance)) {
      pair.complete();
      f(j, static_cast<const NeighborPair<T, D>&>(pair));
    }
  };
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x) {
        const Index c = grid.linear_index(Vec<int, D>{{x, y, z}});
        const std::uint32_t begin = s.targets.offsets[c], end = s.targets.offsets[c + 1];
        if (ordered)
          for (std::uint32_t k = begin; k < end; ++k) visit(k);
        else
          for (std::uint32_t k = begin; k < end; ++k) visit(s.targets.particles[k]);
      }
}

// The views of iter::for_each_neighbor, walked by the slides' iterator loop.
template <iter::CellOrder Order, class F>
UNISPH_HOST_DEVICE void iterator_neighbors_in(const NeighborSearch<T, D>& s, Index i, const Position& xi,
                                              const Vec<int, D>& cell, F& f) {
  using Particles = iter::View<iter::CellParticles<T, D, Order>, direction::Forward, collectivity::None,
                               iter::CompileTimeTuple<>>;
  const iter::CellListArrays<T, D> arrays(s.targets);
  const iter::View<iter::CellBlock<T, D, Order>, direction::Forward, collectivity::None, iter::CompileTimeTuple<>,
                   Particles>
      cells(iter::CellBlock<T, D, Order>::around(arrays, s.targets.grid.cells, cell, s.targets.grid.reach));
  for (auto slot : cells) {  // no padding (one worker, offset 0, jump 1): every slot is valid
    NeighborPair<T, D> pair;
    if (s.targets.grid.test_pair(xi, *slot, pair.r_ij, pair.squared_distance)) {
      const Index j = iter::particle_index(arrays.positions, slot);
      if (s.inner && j == i) continue;
      pair.complete();
      f(j, static_cast<const NeighborPair<T, D>&>(pair));
    }
  }
}
template <class F>
UNISPH_HOST_DEVICE void iterator_neighbors(const NeighborSearch<T, D>& s, Index i, F& f) {
  const Position xi = s.sources[i];
  const CellPlacement<D> at = s.targets.grid.place(xi);
  if (at.status & placement_non_finite) return;
  if (s.inner && s.targets.flag_outside && at.status != placement_inside) return;
  if (s.targets.in_cell_order())
    iterator_neighbors_in<iter::CellOrder::contiguous>(s, i, xi, at.cell, f);
  else
    iterator_neighbors_in<iter::CellOrder::indexed>(s, i, xi, at.cell, f);
}

template <int L>
struct SumW {
  NeighborSearch<T, D> search;
  unisph::View<T> sums;
  unisph::View<std::uint32_t> counts;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    const WendlandC2 w;
    T sum = 0;
    std::uint32_t n = 0;
    auto body = [&](Index, const NeighborPair<T, D>& pair) {
      sum += w(pair.distance());
      ++n;
    };
    if constexpr (L == by_for_each)
      iter::for_each_neighbor(search, i, body);
    else if constexpr (L == by_iterators)
      iterator_neighbors(search, i, body);
    else if constexpr (L == by_hand)
      hand_neighbors(search, i, body);
    else
      search.for_each_direct_neighbor(i, body);
    sums[i] = sum;
    counts[i] = n;
  }
};

// The jittered lattice in cell order (sorted by cell, then by lattice index) or shuffled.
std::vector<Position> lattice(bool cell_order, const SearchGrid<T, D>& grid) {
  const Index n = Index(side) * side * side;
  std::vector<Position> x(n);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<T> jitter(-0.1f * dx, 0.1f * dx);
  for (Index k = 0; k < n; ++k)
    x[k] = {{T(k % side) * dx + jitter(rng), T((k / side) % side) * dx + jitter(rng), T(k / (side * side)) * dx + jitter(rng)}};
  if (cell_order)
    std::stable_sort(x.begin(), x.end(), [&](const Position& a, const Position& b) {
      return grid.linear_index(grid.place(a).cell) < grid.linear_index(grid.place(b).cell);
    });
  else
    std::shuffle(x.begin(), x.end(), rng);
  return x;
}

template <class P, int L>
void Neighbors(benchmark::State& state, bool cell_order) {
  if (skip_unavailable<P>(state)) return;
  const Box<T, D> box{Position::constant(-0.5f * dx), Position::constant((T(side) - 0.5f) * dx)};
  DiscreteVariable<Position> positions("Lattice");
  CellLinkedList<T, D> cells(positions, box, cutoff);
  positions.assign(lattice(cell_order, cells.grid()));
  // Built on seq, so that the order inside each cell (that of the counting atomics) is the same in
  // every run, and so is every particle's sum: the checksums of all runs agree bit for bit.
  cells.build(seq);
  if (cells.report().in_cell_order != cell_order) {
    state.SkipWithError("the lattice is not in the intended order");
    return;
  }
  InnerRelation<T, D> relation(cells, SearchMethod::direct);
  const Index n = positions.size();
  DiscreteVariable<T> sums("sums", n);
  DiscreteVariable<std::uint32_t> counts("counts", n);
  const SumW<L> kernel{relation.direct_search(P{}), sums.write(P{}), counts.write(P{})};
  particle_for(P{}, n, kernel);  // warm-up
  fence(P{});
  for (auto _ : state) {
    particle_for(P{}, n, kernel);
    fence(P{});
  }
  double checksum = 0, pairs = 0;
  for (T v : sums.to_vector()) checksum += double(v);
  for (std::uint32_t c : counts.to_vector()) pairs += double(c);
  state.counters["checksum"] = checksum;
  state.counters["pairs"] = pairs;
  state.counters["particles"] = double(n);
  state.counters["pairs/s"] = benchmark::Counter(pairs * double(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel("policy=" + std::string(P::name) + ", FP32, " + (cell_order ? "cell order" : "any order"));
}
template <class P, int L>
void NeighborsCellOrder(benchmark::State& state) { Neighbors<P, L>(state, true); }
template <class P, int L>
void NeighborsAnyOrder(benchmark::State& state) { Neighbors<P, L>(state, false); }

}  // namespace nb

// ---- package loops: every data point of a sparse grid ------------------------------------------------

namespace pk {
constexpr int D = 3;
constexpr Index points = package_points<D>;

// The kernel of "hand" and "engine": kernel(package, local point).
struct ByDataPoint {
  unisph::View<const Real> in;
  unisph::View<Real> out;
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package, int local) const {
    const Index k = Index(package) * points + Index(local);
    out[k] = Real(2) * in[k] + Real(local);
  }
};

// "hand": data_point_for as it was before it walked views (commit 95da0ed), a flat loop with one
// item per data point.
template <class F>
struct SplitDataPoint {
  F kernel;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    kernel(std::uint32_t(i / points + far_field_packages), int(i % points));
  }
};
template <class P, class F>
void flat_data_point_for(P policy, const PackageMesh<D>& mesh, const F& kernel) {
  particle_for(policy, mesh.data_packages() * points, SplitDataPoint<F>{kernel});
}

// One package per item: a view of that package (offset q, jump the package count) with its
// child view of the 4^3 points.
template <bool ForEach>
struct ByView {
  iter::DataPackages<const Real, D> packages;
  Real* out;
  UNISPH_HOST_DEVICE void operator()(Index q) const {
    using Points = iter::View<iter::PackagePoints<const Real, D>, direction::Forward, collectivity::None,
                              iter::CompileTimeTuple<>>;
    const iter::View<iter::DataPackages<const Real, D>, direction::Forward, collectivity::None, RuntimeTuple, Points>
        view(packages, RuntimeTuple{q, all, packages.packages}, Points(nullptr));
    const auto body = [&](iter::SlotRef<const Real> slot) {
      if (!slot) return;
      const Index k = Index(slot.get() - packages.values);
      out[k] = Real(2) * *slot + Real(k % points);
    };
    if constexpr (ForEach)
      view.for_each(body);
    else
      for (auto slot : view) body(slot);
  }
};

// One package per item and a plain loop over its points.
struct ByPackage {
  unisph::View<const Real> in;
  unisph::View<Real> out;
  UNISPH_HOST_DEVICE void operator()(Index q) const {
    const Index base = (q + iter::first_data_package) * points;
    for (Index l = 0; l < points; ++l) out[base + l] = Real(2) * in[base + l] + Real(l);
  }
};

// A team of 4^3 workers per package (collective_for: a CUDA block of 64 threads on the device):
// the package's view with the points' child view shared by the team, one point per worker, the
// device form of data_point_for's thread per data point written with views.
struct ByTeam {
  iter::DataPackages<const Real, D> packages;
  Real* out;
  template <class Team>
  UNISPH_HOST_DEVICE void operator()(const Team& team, Index q) const {
    using Points = iter::View<iter::PackagePoints<const Real, D>, direction::Forward, Team, iter::CompileTimeTuple<>>;
    const iter::View<iter::DataPackages<const Real, D>, direction::Forward, collectivity::None, RuntimeTuple, Points>
        view(packages, RuntimeTuple{q, all, packages.packages}, Points(nullptr, {}, iter::NoChild{}, team));
    view.for_each([&](iter::SlotRef<const Real> slot) {
      if (!slot) return;
      const Index k = Index(slot.get() - packages.values);
      out[k] = Real(2) * *slot + Real(k % points);
    });
  }
};

enum Loop { by_flat_loop, by_engine, by_for_each, by_iterators, by_plain_package, by_team };

template <class P, int L>
void Packages(benchmark::State& state) {
  if (skip_unavailable<P>(state)) return;
  const int cells = 48;
  PackageMesh<D> mesh(PackageGrid<D>{Vec<Real, D>{{0, 0, 0}}, Real(0.25), Vec<int, D>{{cells, cells, cells}}});
  DiscreteVariable<CellTag> tags("Tags", mesh.grid().cell_count());
  {
    std::vector<CellTag> host(mesh.grid().cell_count(), CellTag::core);
    tags.assign(host);
  }
  mesh.allocate(P{}, tags);
  const Index n = mesh.packages() * points;
  DiscreteVariable<Real> in("in", n), out("out", n);
  {
    std::vector<Real> host(n);
    for (Index k = 0; k < n; ++k) host[k] = Real(k % 1000);
    in.assign(host);
  }
  const unisph::View<const Real> x = in.read(P{});
  const unisph::View<Real> y = out.write(P{});
  const iter::DataPackages<const Real, D> packages{x.data(), mesh.packages()};
  const auto run = [&] {
    if constexpr (L == by_flat_loop)
      flat_data_point_for(P{}, mesh, ByDataPoint{x, y});
    else if constexpr (L == by_engine)
      data_point_for(P{}, mesh, ByDataPoint{x, y});
    else if constexpr (L == by_for_each)
      particle_for(P{}, mesh.data_packages(), ByView<true>{packages, y.data()});
    else if constexpr (L == by_iterators)
      particle_for(P{}, mesh.data_packages(), ByView<false>{packages, y.data()});
    else if constexpr (L == by_team)
      iter::collective_for(P{}, mesh.data_packages(), points, ByTeam{packages, y.data()});
    else
      particle_for(P{}, mesh.data_packages(), ByPackage{x, y});
  };
  run();  // warm-up
  fence(P{});
  for (auto _ : state) {
    run();
    fence(P{});
  }
  state.counters["checksum"] = host_total(out);
  state.counters["data_points"] = double(mesh.data_packages() * points);
  state.counters["bytes/s"] = benchmark::Counter(double(mesh.data_packages() * points) * 2 * sizeof(Real) *
                                                     double(state.iterations()),
                                                 benchmark::Counter::kIsRate);
  state.SetLabel("policy=" + std::string(P::name));
}
}  // namespace pk

using nb::NeighborsAnyOrder;
using nb::NeighborsCellOrder;
using pk::Packages;

#define UNISPH_VIEWS_BENCHMARK(CASE, LOOP, ...) \
  BENCHMARK_TEMPLATE(__VA_ARGS__)->Name(CASE "/" LOOP)->UseRealTime()->Unit(benchmark::kMillisecond);
#define UNISPH_NEIGHBOR_BENCHMARKS(P, policy_name, CASE, FN)                                    \
  UNISPH_VIEWS_BENCHMARK(CASE, "for_each/" policy_name, FN, P, nb::by_for_each)                  \
  UNISPH_VIEWS_BENCHMARK(CASE, "view/" policy_name, FN, P, nb::by_iterators)                     \
  UNISPH_VIEWS_BENCHMARK(CASE, "hand/" policy_name, FN, P, nb::by_hand)                          \
  UNISPH_VIEWS_BENCHMARK(CASE, "direct/" policy_name, FN, P, nb::by_direct_search)
#define UNISPH_VIEWS_BENCHMARKS(P, policy_name)                                                  \
  UNISPH_VIEWS_BENCHMARK("all_particles", "view/" policy_name, PerSupercell, P, AllView<iterator_loop>)     \
  UNISPH_VIEWS_BENCHMARK("all_particles", "for_each/" policy_name, PerSupercell, P, AllView<for_each_loop>)  \
  UNISPH_VIEWS_BENCHMARK("all_particles", "nested/" policy_name, PerSupercell, P, AllView<nested_loop>)      \
  UNISPH_VIEWS_BENCHMARK("all_particles", "hand/" policy_name, PerSupercell, P, AllHand)                    \
  UNISPH_VIEWS_BENCHMARK("strided", "view/" policy_name, PerSupercell, P, StridedView<iterator_loop>)       \
  UNISPH_VIEWS_BENCHMARK("strided", "for_each/" policy_name, PerSupercell, P, StridedView<for_each_loop>)    \
  UNISPH_VIEWS_BENCHMARK("strided", "nested/" policy_name, PerSupercell, P, StridedView<nested_loop>)       \
  UNISPH_VIEWS_BENCHMARK("strided", "hand/" policy_name, PerSupercell, P, StridedHand)               \
  UNISPH_NEIGHBOR_BENCHMARKS(P, policy_name, "neighbors_cell_order", NeighborsCellOrder)         \
  UNISPH_NEIGHBOR_BENCHMARKS(P, policy_name, "neighbors_any_order", NeighborsAnyOrder)           \
  UNISPH_VIEWS_BENCHMARK("packages", "hand/" policy_name, Packages, P, pk::by_flat_loop)         \
  UNISPH_VIEWS_BENCHMARK("packages", "engine/" policy_name, Packages, P, pk::by_engine)          \
  UNISPH_VIEWS_BENCHMARK("packages", "for_each/" policy_name, Packages, P, pk::by_for_each)      \
  UNISPH_VIEWS_BENCHMARK("packages", "view/" policy_name, Packages, P, pk::by_iterators)         \
  UNISPH_VIEWS_BENCHMARK("packages", "plain/" policy_name, Packages, P, pk::by_plain_package)

UNISPH_VIEWS_BENCHMARKS(SequencedPolicy, "seq")
UNISPH_VIEWS_BENCHMARKS(ParallelPolicy, "par")
#if UNISPH_HAS_CUDA && defined(__CUDACC__)
UNISPH_VIEWS_BENCHMARKS(ParallelDevicePolicy, "device")
UNISPH_VIEWS_BENCHMARK("all_particles", "view/team", PerTeam, TeamView<false, iterator_loop>)
UNISPH_VIEWS_BENCHMARK("all_particles", "for_each/team", PerTeam, TeamView<false, for_each_loop>)
UNISPH_VIEWS_BENCHMARK("all_particles", "nested/team", PerTeam, TeamView<false, nested_loop>)
UNISPH_VIEWS_BENCHMARK("all_particles", "hand/team", PerTeam, TeamHand<false>)
UNISPH_VIEWS_BENCHMARK("strided", "view/team", PerTeam, TeamView<true, iterator_loop>)
UNISPH_VIEWS_BENCHMARK("strided", "for_each/team", PerTeam, TeamView<true, for_each_loop>)
UNISPH_VIEWS_BENCHMARK("strided", "nested/team", PerTeam, TeamView<true, nested_loop>)
UNISPH_VIEWS_BENCHMARK("strided", "hand/team", PerTeam, TeamHand<true>)
UNISPH_VIEWS_BENCHMARK("packages", "team/device", Packages, ParallelDevicePolicy, pk::by_team)
#endif

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  const ExecutionInfo& info = execution_info();
  benchmark::AddCustomContext("unisph_host_threads", std::to_string(host_threads()));
  benchmark::AddCustomContext("unisph_gpu", policy_available(PolicyKind::device) ? info.device_name
                                                                                 : info.device_unavailable_reason);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
