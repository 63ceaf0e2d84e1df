// Views over unisph's own hierarchies (iter/cell_list_traits.hpp, iter/package_traits.hpp):
// (each walk by the iterators, by for_each and by children(), the range of child views)
// cells of a cell linked list -> their particles, and data packages of a sparse grid -> their
// 4^D data points. Every walk runs inside a kernel on every policy and is compared with a plain
// loop over the same arrays on the host: forward and backward at both levels, offsets, jumps
// (larger than the count too), element counts, empty cells, particles in any order and in cell
// order; then a team (a CUDA block / std::threads with a barrier) sharing each cell's and each
// package's walk with a sync() on every trip, every particle and every point visited once.
#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/atomic.hpp"
#include "unisph/grid/package_for.hpp"
#include "unisph/grid/package_mesh.hpp"
#include "unisph/neighbor/cell_list_traits.hpp"
#include "unisph/iter/collective_for.hpp"
#include "unisph/grid/package_traits.hpp"
#include "unisph/iter/view.hpp"

namespace {
using namespace unisph;
using iter::all;
using iter::CellOrder;
using iter::RuntimeTuple;
namespace direction = iter::direction;
namespace collectivity = iter::collectivity;

using T = float;
constexpr int D = 3;
using Position = Vec<T, D>;

// ---- what a walk visits, recorded in a kernel ---------------------------------------------------

// Item g walks make(g) three times, with the iterators, with for_each and with a range-for per
// level over children(), and records what each slot holds (make.id(slot), or -1 for an invalid
// slot), at most `capacity` slots per item.
template <class Maker>
struct RecordWalk {
  Maker make;
  Index capacity;
  unisph::View<long long> by_iterator, by_for_each, by_children;
  unisph::View<Index> iterator_slots, for_each_slots, children_slots;
  UNISPH_HOST_DEVICE void operator()(Index g) const {
    const auto view = make(g);
    Index n = 0;
    for (auto slot : view) {
      if (n < capacity) by_iterator[g * capacity + n] = slot ? make.id(slot) : -1;
      ++n;
    }
    iterator_slots[g] = n;
    Index m = 0;
    view.for_each([&](auto slot) {
      if (m < capacity) by_for_each[g * capacity + m] = slot ? make.id(slot) : -1;
      ++m;
    });
    for_each_slots[g] = m;
    Index l = 0;
    for (auto child : view.children())
      for (auto slot : child) {
        if (l < capacity) by_children[g * capacity + l] = slot ? make.id(slot) : -1;
        ++l;
      }
    children_slots[g] = l;
  }
};

// The positions a level visits by the rule of iter/view.hpp (trips = ceil(C / j) - floor(o / j),
// positions at or past C invalid), as element indices (counted from the end walking backward) or -1.
std::vector<long long> plain_level(Index size, RuntimeTuple r, bool forward) {
  const Index count = std::min(r.count, size);
  const Index rounds = (count + r.jump - 1) / r.jump, skipped = r.offset / r.jump;
  const Index trips = skipped < rounds ? rounds - skipped : 0;
  std::vector<long long> out;
  for (Index t = 0, p = r.offset; t < trips; ++t, p += r.jump)
    out.push_back(p < count ? (long long)(forward ? p : size - 1 - p) : -1);
  return out;
}

// A two-level walk as plain loops: for each visited parent element, its child's visited slots.
// An invalid parent (padding) has an empty child: no slots where the child's size is known at
// run time (cells), `fixed_child_slots` invalid slots where it is a compile-time trait (the 4^D
// points of a package, like a frame's N slots, so that team walks keep equal trip counts). A
// parent whose child walk is empty yields nothing.
template <class ChildSize, class Element>
std::vector<long long> plain_nested(Index parents, RuntimeTuple parent, bool parent_forward, RuntimeTuple child,
                                    bool child_forward, ChildSize child_size, Element element,
                                    Index fixed_child_slots = 0) {
  std::vector<long long> out;
  for (long long p : plain_level(parents, parent, parent_forward)) {
    const Index n = p < 0 ? fixed_child_slots : child_size(Index(p));
    for (long long k : plain_level(n, child, child_forward))
      out.push_back(k < 0 || p < 0 ? -1 : element(Index(p), Index(k)));
  }
  return out;
}

template <class Policy, class Maker>
void expect_walks(Policy policy, const Maker& make, Index items, Index capacity,
                  const std::vector<std::vector<long long>>& expected, const std::string& where) {
  DiscreteVariable<long long> a("by_iterator", items * capacity), b("by_for_each", items * capacity),
      c("by_children", items * capacity);
  DiscreteVariable<Index> na("iterator_slots", items), nb("for_each_slots", items), nc("children_slots", items);
  particle_for(policy, items,
               RecordWalk<Maker>{make, capacity, a.write(policy), b.write(policy), c.write(policy), na.write(policy),
                                 nb.write(policy), nc.write(policy)});
  const std::vector<long long> ha = a.to_vector(), hb = b.to_vector(), hc = c.to_vector();
  const std::vector<Index> hna = na.to_vector(), hnb = nb.to_vector(), hnc = nc.to_vector();
  for (Index g = 0; g < items; ++g) {
    ASSERT_LE(expected[g].size(), capacity) << where;
    ASSERT_EQ(hna[g], expected[g].size()) << where << ", item " << g;
    ASSERT_EQ(hnb[g], expected[g].size()) << where << ", item " << g;
    const std::vector<long long> got_a(ha.begin() + g * capacity, ha.begin() + g * capacity + hna[g]);
    const std::vector<long long> got_b(hb.begin() + g * capacity, hb.begin() + g * capacity + hnb[g]);
    ASSERT_EQ(got_a, expected[g]) << where << ", item " << g << " (iterators)";
    ASSERT_EQ(got_b, expected[g]) << where << ", item " << g << " (for_each)";
    ASSERT_EQ(hnc[g], expected[g].size()) << where << ", item " << g;
    const std::vector<long long> got_c(hc.begin() + g * capacity, hc.begin() + g * capacity + hnc[g]);
    ASSERT_EQ(got_c, expected[g]) << where << ", item " << g << " (children)";
  }
}

// ---- a cell linked list ----------------------------------------------------------------------------

// 3000 particles in [0, 0.7]^3 of the box [0, 1]^3 with cutoff 0.25: 5 cells per axis, about
// 24 particles in each cell below 0.75, the cells beyond empty.
struct CellListCase {
  Box<T, D> box{Position::constant(T(0)), Position::constant(T(1))};
  T cutoff = T(0.25);
  DiscreteVariable<Position> positions{"ViewParticles"};
  CellLinkedList<T, D> list{positions, box, cutoff};
  std::vector<std::uint32_t> offsets, particles;

  template <class P>
  CellListCase(P policy, bool cell_order) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0.0, 0.7);
    std::vector<Position> x(3000);
    for (Position& p : x)
      for (int a = 0; a < D; ++a) p[a] = T(u(rng));
    if (cell_order) {
      const SearchGrid<T, D> grid = list.grid();
      std::stable_sort(x.begin(), x.end(), [&](const Position& a, const Position& b) {
        return grid.linear_index(grid.place(a).cell) < grid.linear_index(grid.place(b).cell);
      });
    }
    positions.assign(x);
    list.build(policy);
    offsets = list.offsets().to_vector();
    particles = list.particles().to_vector();
  }
  // The particle at CSR place k.
  long long particle_at(Index k, CellOrder order) const {
    return order == CellOrder::contiguous ? (long long)k : (long long)particles[k];
  }
};

template <CellOrder Order, class CellDirection, class ParticleDirection>
struct CellsOfListWalk {
  iter::CellsOfList<T, D, Order> cells;
  RuntimeTuple cell_runtime, particle_runtime;
  Index items;  // item g starts g jumps further and every item jumps `items` times as far
  using Particles = iter::View<iter::CellParticles<T, D, Order>, ParticleDirection, collectivity::None, RuntimeTuple>;
  using Cells = iter::View<iter::CellsOfList<T, D, Order>, CellDirection, collectivity::None, RuntimeTuple, Particles>;
  UNISPH_HOST_DEVICE Cells operator()(Index g) const {
    const RuntimeTuple r{cell_runtime.offset + g * cell_runtime.jump, cell_runtime.count, cell_runtime.jump * items};
    return Cells(cells, r, Particles(nullptr, particle_runtime));
  }
  UNISPH_HOST_DEVICE long long id(iter::SlotRef<const Position> slot) const {
    return (long long)iter::particle_index(cells.arrays.positions, slot);
  }
};

// Item i walks the block of cells within reach 1 of particle i's cell.
template <CellOrder Order, class CellDirection, class ParticleDirection>
struct CellBlockWalk {
  CellListView<T, D> list;
  RuntimeTuple particle_runtime;
  using Particles = iter::View<iter::CellParticles<T, D, Order>, ParticleDirection, collectivity::None, RuntimeTuple>;
  using Cells = iter::View<iter::CellBlock<T, D, Order>, CellDirection, collectivity::None, RuntimeTuple, Particles>;
  UNISPH_HOST_DEVICE Cells operator()(Index i) const {
    const iter::CellListArrays<T, D> arrays(list);
    return Cells(iter::CellBlock<T, D, Order>::around(arrays, list.grid.cells, list.grid.place(list.positions[i]).cell, 1),
                 RuntimeTuple{}, Particles(nullptr, particle_runtime));
  }
  UNISPH_HOST_DEVICE long long id(iter::SlotRef<const Position> slot) const {
    return (long long)iter::particle_index(list.positions.data(), slot);
  }
};

template <CellOrder Order, class CellDirection, class ParticleDirection, class P>
void check_cell_walks(P policy, CellListCase& c) {
  const Index cells = c.list.cell_count();
  const auto size_of = [&](Index cell) { return Index(c.offsets[cell + 1] - c.offsets[cell]); };
  const auto particle = [&](Index cell, Index k) { return c.particle_at(c.offsets[cell] + k, Order); };
  const CellListView<T, D> view = c.list.view(policy);
  const iter::CellsOfList<T, D, Order> all_cells{iter::CellListArrays<T, D>(view), cells};
  for (const RuntimeTuple cell_runtime : {RuntimeTuple{0, all, 1}, RuntimeTuple{3, all, 2}, RuntimeTuple{1, 40, 150}})
    for (const RuntimeTuple particle_runtime : {RuntimeTuple{0, all, 1}, RuntimeTuple{1, all, 3}, RuntimeTuple{2, 5, 7},
                                                RuntimeTuple{5, all, 100}})
      for (const Index items : {Index(1), Index(7)}) {
        std::vector<std::vector<long long>> expected;
        for (Index g = 0; g < items; ++g)
          expected.push_back(plain_nested(
              cells,
              RuntimeTuple{cell_runtime.offset + g * cell_runtime.jump, cell_runtime.count, cell_runtime.jump * items},
              CellDirection::is_forward, particle_runtime, ParticleDirection::is_forward, size_of, particle));
        const std::string where = "cells (" + std::to_string(cell_runtime.offset) + ", " +
                                  std::to_string(cell_runtime.count) + ", " + std::to_string(cell_runtime.jump) +
                                  ") particles (" + std::to_string(particle_runtime.offset) + ", " +
                                  std::to_string(particle_runtime.count) + ", " + std::to_string(particle_runtime.jump) +
                                  "), " + std::to_string(items) + " items";
        expect_walks(policy,
                     CellsOfListWalk<Order, CellDirection, ParticleDirection>{all_cells, cell_runtime, particle_runtime,
                                                                               items},
                     items, 4096, expected, where);
      }

  // The 3^3 blocks around the first 200 particles, against nested plain loops over the block.
  const SearchGrid<T, D> grid = c.list.grid();
  const std::vector<Position> x = c.positions.to_vector();
  const Index sources = 200;
  for (const RuntimeTuple particle_runtime : {RuntimeTuple{0, all, 1}, RuntimeTuple{1, all, 2}}) {
    std::vector<std::vector<long long>> expected(sources);
    for (Index i = 0; i < sources; ++i) {
      const Vec<int, D> cell = grid.place(x[i]).cell;
      std::vector<Index> block;
      for (int z = std::max(cell[2] - 1, 0); z <= std::min(cell[2] + 1, grid.cells[2] - 1); ++z)
        for (int y = std::max(cell[1] - 1, 0); y <= std::min(cell[1] + 1, grid.cells[1] - 1); ++y)
          for (int xx = std::max(cell[0] - 1, 0); xx <= std::min(cell[0] + 1, grid.cells[0] - 1); ++xx)
            block.push_back(grid.linear_index(Vec<int, D>{{xx, y, z}}));
      if (!CellDirection::is_forward) std::reverse(block.begin(), block.end());
      expected[i] = plain_nested(
          block.size(), RuntimeTuple{}, true, particle_runtime, ParticleDirection::is_forward,
          [&](Index b) { return size_of(block[b]); }, [&](Index b, Index k) { return particle(block[b], k); });
    }
    expect_walks(policy, CellBlockWalk<Order, CellDirection, ParticleDirection>{view, particle_runtime}, sources, 4096,
                 expected, "3^3 blocks, particles (" + std::to_string(particle_runtime.offset) + ", all, " +
                               std::to_string(particle_runtime.jump) + ")");
  }
}

UNISPH_POLICY_TEST_SUITE(CellListViews);

TYPED_TEST(CellListViews, WalksOverParticlesInAnyOrderMatchPlainLoops) {
  CellListCase c(this->policy, false);
  ASSERT_FALSE(c.list.report().in_cell_order);
  check_cell_walks<CellOrder::indexed, direction::Forward, direction::Forward>(this->policy, c);
  check_cell_walks<CellOrder::indexed, direction::Backward, direction::Forward>(this->policy, c);
  check_cell_walks<CellOrder::indexed, direction::Forward, direction::Backward>(this->policy, c);
  check_cell_walks<CellOrder::indexed, direction::Backward, direction::Backward>(this->policy, c);
}

TYPED_TEST(CellListViews, WalksOverParticlesInCellOrderMatchPlainLoops) {
  CellListCase c(this->policy, true);
  ASSERT_TRUE(c.list.report().in_cell_order);
  check_cell_walks<CellOrder::contiguous, direction::Forward, direction::Forward>(this->policy, c);
  check_cell_walks<CellOrder::contiguous, direction::Backward, direction::Backward>(this->policy, c);
}

// A team of 32 per cell shares the walk over the cell's particles, with a barrier on every trip.
constexpr Index cell_team = 32;

template <CellOrder Order>
struct TeamOverCells {
  iter::CellsOfList<T, D, Order> cells;
  unisph::View<unsigned> visits;  // per particle
  unisph::View<Index> trips;      // per cell and rank
  template <class Team>
  UNISPH_HOST_DEVICE void operator()(const Team& team, Index c) const {
    using Particles = iter::View<iter::CellParticles<T, D, Order>, direction::Forward, Team, RuntimeTuple>;
    // Only cell c: offset c with a jump of the cell count.
    const iter::View<iter::CellsOfList<T, D, Order>, direction::Forward, collectivity::None, RuntimeTuple, Particles>
        view(cells, RuntimeTuple{c, all, cells.cells}, Particles(nullptr, RuntimeTuple{}, iter::NoChild{}, team));
    Index t = 0;
    for (auto slot : view) {
      if (slot) atomic_add(&visits[iter::particle_index(cells.arrays.positions, slot)], 1u);
      team.sync();  // every rank makes the same number of trips, so all of them get here
      ++t;
    }
    trips[c * cell_team + team.rank()] = t;
  }
};

TYPED_TEST(CellListViews, ATeamPerCellVisitsEveryParticleOnceWithABarrierOnEveryTrip) {
  CellListCase c(this->policy, false);
  const Index cells = c.list.cell_count(), n = c.positions.size();
  DiscreteVariable<unsigned> visits("visits", n);
  DiscreteVariable<Index> trips("trips", cells * cell_team);
  const CellListView<T, D> view = c.list.view(this->policy);
  iter::collective_for(this->policy, cells, cell_team,
                       TeamOverCells<CellOrder::indexed>{{iter::CellListArrays<T, D>(view), cells},
                                                         visits.read_write(this->policy), trips.write(this->policy)});
  fence(this->policy);
  const std::vector<unsigned> v = visits.to_vector();
  EXPECT_EQ(std::count(v.begin(), v.end(), 1u), Index(n)) << "every particle once";
  const std::vector<Index> t = trips.to_vector();
  for (Index cell = 0; cell < cells; ++cell) {
    const Index size = c.offsets[cell + 1] - c.offsets[cell];
    for (Index r = 0; r < cell_team; ++r)
      ASSERT_EQ(t[cell * cell_team + r], (size + cell_team - 1) / cell_team) << "cell " << cell << " rank " << r;
  }
}

// ---- a package mesh ------------------------------------------------------------------------------

PackageGrid<3> package_grid() {
  return PackageGrid<3>{Vec<Real, 3>{{-1.0, -2.0, 0.5}}, Real(0.125), Vec<int, 3>{{13, 11, 9}}};
}

// Core where a spherical shell passes, inner around it, the rest inside or outside.
std::vector<CellTag> shell_tags(const PackageGrid<3>& grid) {
  std::vector<CellTag> tags(grid.cell_count());
  const Vec<Real, 3> centre{{-1.0 + 6.5 * 0.5, -2.0 + 5.5 * 0.5, 0.5 + 4.5 * 0.5}};
  for (Index c = 0; c < tags.size(); ++c) {
    const Real r = norm(grid.cell_centre(grid.coordinates(c)) - centre);
    tags[c] = r < 1.2 ? CellTag::inside : CellTag::outside;
    if (r > 1.2 - 0.5 && r < 1.2 + 0.5) tags[c] = CellTag::core;
    else if (r > 1.2 - 1.0 && r < 1.2 + 1.0) tags[c] = CellTag::inner;
  }
  return tags;
}

constexpr Index points = package_points<3>;

template <class PackageDirection, class PointDirection>
struct PackageWalk {
  iter::DataPackages<const Real, 3> packages;
  RuntimeTuple package_runtime, point_runtime;
  Index items;
  using Points = iter::View<iter::PackagePoints<const Real, 3>, PointDirection, collectivity::None, RuntimeTuple>;
  using Packages = iter::View<iter::DataPackages<const Real, 3>, PackageDirection, collectivity::None, RuntimeTuple, Points>;
  UNISPH_HOST_DEVICE Packages operator()(Index g) const {
    const RuntimeTuple r{package_runtime.offset + g * package_runtime.jump, package_runtime.count,
                         package_runtime.jump * items};
    return Packages(packages, r, Points(nullptr, point_runtime));
  }
  UNISPH_HOST_DEVICE long long id(iter::SlotRef<const Real> slot) const {
    const DataPointAddress a = iter::data_point_of<const Real, 3>(packages.values, slot);
    return (long long)a.package * (long long)points + a.local_point;
  }
};

// What data_point_for visits: one mark per (package, point).
struct MarkDataPoint {
  unisph::View<unsigned> marks;
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package, int local) const {
    atomic_add(&marks[Index(package) * points + Index(local)], 1u);
  }
};

// A block of 64 threads per package, one data point each, with a barrier on every trip.
struct TeamOverPackages {
  iter::DataPackages<const Real, 3> packages;
  unisph::View<unsigned> marks;
  unisph::View<Index> trips;  // per package and rank
  template <class Team>
  UNISPH_HOST_DEVICE void operator()(const Team& team, Index g) const {
    using Points = iter::View<iter::PackagePoints<const Real, 3>, direction::Forward, Team, RuntimeTuple>;
    const iter::View<iter::DataPackages<const Real, 3>, direction::Forward, collectivity::None, RuntimeTuple, Points>
        view(packages, RuntimeTuple{g, all, packages.packages}, Points(nullptr, RuntimeTuple{}, iter::NoChild{}, team));
    Index t = 0;
    for (auto slot : view) {
      if (slot) {
        const DataPointAddress a = iter::data_point_of<const Real, 3>(packages.values, slot);
        atomic_add(&marks[Index(a.package) * points + Index(a.local_point)], 1u);
      }
      team.sync();
      ++t;
    }
    trips[g * points + team.rank()] = t;
  }
};

template <class PackageDirection, class PointDirection, class P>
void check_package_walks(P policy, PackageMesh<3>& mesh, DiscreteVariable<Real>& field) {
  const Index data_packages = mesh.data_packages();
  const iter::DataPackages<const Real, 3> packages{field.read(policy).data(), mesh.packages()};
  for (const RuntimeTuple package_runtime : {RuntimeTuple{0, all, 1}, RuntimeTuple{2, all, 3}, RuntimeTuple{1, 10, 40}})
    for (const RuntimeTuple point_runtime : {RuntimeTuple{0, all, 1}, RuntimeTuple{1, all, 5}, RuntimeTuple{3, 2, 70}})
      for (const Index items : {Index(1), Index(5)}) {
        // A package's point count is fixed at 4^3 (a compile-time trait, like a frame's slots):
        // the view ignores the runtime count, and so does the plain loop.
        const RuntimeTuple point_loop{point_runtime.offset, all, point_runtime.jump};
        std::vector<std::vector<long long>> expected;
        for (Index g = 0; g < items; ++g)
          expected.push_back(plain_nested(
              data_packages,
              RuntimeTuple{package_runtime.offset + g * package_runtime.jump, package_runtime.count,
                           package_runtime.jump * items},
              PackageDirection::is_forward, point_loop, PointDirection::is_forward,
              [](Index) { return points; },
              [](Index q, Index k) { return (long long)((q + iter::first_data_package) * points + k); }, points));
        const std::string where = "packages (" + std::to_string(package_runtime.offset) + ", " +
                                  std::to_string(package_runtime.count) + ", " + std::to_string(package_runtime.jump) +
                                  ") points (" + std::to_string(point_runtime.offset) + ", " +
                                  std::to_string(point_runtime.jump) + "), " + std::to_string(items) + " items";
        expect_walks(policy,
                     PackageWalk<PackageDirection, PointDirection>{packages, package_runtime, point_runtime, items},
                     items, data_packages * points + 64, expected, where);
      }
}

UNISPH_POLICY_TEST_SUITE(PackageViews);

TYPED_TEST(PackageViews, WalksOverDataPointsMatchPlainLoopsAndDataPointFor) {
  PackageMesh<3> mesh(package_grid());
  DiscreteVariable<CellTag> tags("Tags");
  tags.assign(shell_tags(mesh.grid()));
  mesh.allocate(this->policy, tags);
  ASSERT_GT(mesh.data_packages(), Index(10));
  DiscreteVariable<Real> field("Field", mesh.packages() * points);

  check_package_walks<direction::Forward, direction::Forward>(this->policy, mesh, field);
  check_package_walks<direction::Backward, direction::Forward>(this->policy, mesh, field);
  check_package_walks<direction::Forward, direction::Backward>(this->policy, mesh, field);

  // A team per package visits what data_point_for visits, each point once.
  DiscreteVariable<unsigned> by_loop("by_loop", mesh.packages() * points), by_team("by_team", mesh.packages() * points);
  data_point_for(this->policy, mesh, MarkDataPoint{by_loop.read_write(this->policy)});
  DiscreteVariable<Index> trips("trips", mesh.data_packages() * points);
  iter::collective_for(this->policy, mesh.data_packages(), points,
                       TeamOverPackages{{field.read(this->policy).data(), mesh.packages()},
                                        by_team.read_write(this->policy), trips.write(this->policy)});
  fence(this->policy);
  const std::vector<unsigned> loop = by_loop.to_vector(), team = by_team.to_vector();
  EXPECT_EQ(std::count(loop.begin(), loop.end(), 1u), Index(mesh.data_packages() * points));
  EXPECT_EQ(team, loop);
  const std::vector<Index> t = trips.to_vector();
  EXPECT_EQ(std::count(t.begin(), t.end(), Index(1)), Index(t.size())) << "64 threads, 64 points: one trip each";
}

}  // namespace
