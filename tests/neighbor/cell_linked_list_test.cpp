// The cell linked list: CSR structure (every particle once, in the cell its position says),
// the same on every policy; ordered by id, each cell's particles in ascending id (the
// brute-force order, on every policy); the search grid's geometry and its errors.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <tuple>
#include <vector>

#include "neighbor_scenarios.hpp"
#include "support/policy_test.hpp"
#include "unisph/neighbor/cell_linked_list.hpp"
#include "unisph/particles/body.hpp"

namespace {
using namespace unisph;
using namespace unisph::testing;

template <class T, int D, class P>
void check_structure(P policy, Layout layout) {
  SCOPED_TRACE(std::string(to_string(layout)) + ", " + std::to_string(D) + "D, " + (sizeof(T) == 4 ? "float" : "double"));
  const Scenario<T, D> s = make_scenario<T, D>(layout);
  DiscreteVariable<Vec<T, D>> x("Position");
  x.assign(s.positions);
  CellLinkedList<T, D> cells(x, s.box, s.cutoff);
  cells.build(policy);
  const auto offsets = cells.offsets().to_vector();
  const auto particles = cells.particles().to_vector();
  const Index n = s.positions.size();
  ASSERT_EQ(offsets.size(), cells.cell_count() + 2);
  EXPECT_EQ(offsets.front(), 0u);
  EXPECT_EQ(offsets.back(), n);
  EXPECT_TRUE(std::is_sorted(offsets.begin(), offsets.end()));
  std::vector<int> seen(n, 0);
  Index misplaced = 0;
  for (Index c = 0; c < cells.cell_count(); ++c)
    for (std::uint32_t k = offsets[c]; k < offsets[c + 1]; ++k) {
      const std::uint32_t i = particles[k];
      ASSERT_LT(i, n);
      ++seen[i];
      misplaced += cells.grid().linear_index(cells.grid().place(s.positions[i]).cell) != c;
    }
  EXPECT_EQ(misplaced, 0u);
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int v) { return v == 1; }));
  const CellListReport r = cells.report();
  EXPECT_EQ(r.particles, n);
  EXPECT_EQ(r.out_of_box + r.non_finite + r.flagged, 0u);
  // In cell order exactly when no particle's cell is below its predecessor's.
  bool ordered = true;
  for (Index i = 1; i < n; ++i)
    ordered = ordered && cells.grid().linear_index(cells.grid().place(s.positions[i - 1]).cell) <=
                             cells.grid().linear_index(cells.grid().place(s.positions[i]).cell);
  EXPECT_EQ(r.in_cell_order, ordered);
  if (layout == Layout::random) {
    EXPECT_FALSE(r.in_cell_order);
  }
  // The positions copied into the list's order: exactly those of particles[k], in the padded
  // layout, where the particles are not in cell order (otherwise nothing is copied).
  cells.store_positions_in_cell_order();
  cells.build(policy);
  const auto same_particles = cells.particles().to_vector();
  EXPECT_EQ(same_particles.size(), particles.size());
  if (!ordered) {
    const CellListView<T, D> view = cells.view(seq);
    Index wrong = 0;
    for (Index k = 0; k < n; ++k) {
      const Vec<T, D> p = view.points[k].position();
      wrong += !(p == s.positions[same_particles[k]]);
    }
    EXPECT_EQ(wrong, 0u);
  }
}

UNISPH_POLICY_TEST_SUITE(CellListBuild);

TYPED_TEST(CellListBuild, EveryParticleOnceInItsCell) {
  for (Layout layout : all_layouts) {
    check_structure<float, 2>(this->policy, layout);
    check_structure<double, 2>(this->policy, layout);
    check_structure<float, 3>(this->policy, layout);
    check_structure<double, 3>(this->policy, layout);
  }
}

TYPED_TEST(CellListBuild, FlaggedParticlesGoToTheirOwnBucketAndRebuildsStartClean) {
  const auto policy = this->policy;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  DiscreteVariable<Vec<double, 3>> x("Position", {{{0.5, 0.5, 0.5}}, {{nan, 0.1, 0.1}}, {{2.0, 0.5, 0.5}},
                                                  {{0.0, 0.0, 1.0}}, {{1.0, 1.0, 1.0}}});
  CellLinkedList<double, 3> cells(x, {Vec<double, 3>{}, Vec<double, 3>::constant(1.0)}, 0.25, OutsideParticles::flag);
  for (int build = 0; build < 2; ++build) {
    cells.build(policy);
    const CellListReport r = cells.report();
    EXPECT_EQ(r.out_of_box, 1u);
    EXPECT_EQ(r.non_finite, 1u);
    EXPECT_EQ(r.flagged, 2u);
    const auto offsets = cells.offsets().to_vector();
    const auto particles = cells.particles().to_vector();
    const Index flagged = cells.cell_count();
    std::vector<std::uint32_t> in_bucket(particles.begin() + offsets[flagged], particles.begin() + offsets[flagged + 1]);
    std::sort(in_bucket.begin(), in_bucket.end());
    EXPECT_EQ(in_bucket, (std::vector<std::uint32_t>{1, 2}));
  }
  // The box faces belong to the box: the corner (1, 1, 1) is in the last cell.
  EXPECT_EQ(cells.grid().place({{1.0, 1.0, 1.0}}).status, placement_inside);
  EXPECT_EQ(cells.grid().place({{1.0, 1.0, 1.0}}).cell, (Vec<int, 3>{{4, 4, 4}}));
}

// A grid over part of the region (report_outside_of the whole of it, as the solver's cells cover
// only the particles' box in a wider domain): a particle beyond the grid but inside the region is
// clamped into a border cell and not reported; one beyond the region is; a NaN is non-finite only.
TYPED_TEST(CellListBuild, ReportsLeavingAgainstItsOwnBoxWhereGiven) {
  const auto policy = this->policy;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  DiscreteVariable<Vec<double, 2>> x("Position", {{{0.5, 0.5}}, {{1.5, 0.5}}, {{0.5, 3.5}}, {{nan, 0.5}}, {{1.0, 1.0}}});
  CellLinkedList<double, 2> cells(x, {Vec<double, 2>{}, Vec<double, 2>::constant(1.0)}, 0.25);
  cells.build(policy);
  EXPECT_EQ(cells.report().out_of_box, 2u);  // against the grid's box
  cells.report_outside_of({Vec<double, 2>::constant(-1.0), Vec<double, 2>::constant(3.0)});
  cells.build(policy);
  const CellListReport r = cells.report();
  EXPECT_EQ(r.out_of_box, 1u);  // (0.5, 3.5) only
  EXPECT_EQ(r.non_finite, 1u);
  EXPECT_EQ(r.flagged, 0u);
  // (1.5, 0.5) lies in the border cell of (1, 0.5), where a neighbour search finds it.
  const auto offsets = cells.offsets().to_vector();
  const auto particles = cells.particles().to_vector();
  const Index border = cells.grid().linear_index(cells.grid().place({{1.0, 0.5}}).cell);
  EXPECT_NE(std::find(particles.begin() + offsets[border], particles.begin() + offsets[border + 1], 1u),
            particles.begin() + offsets[border + 1]);
}

// Ordered by id: a set whose owned particles carry shuffled ids from first_id = 1000 on, and
// ghosts after them that carry owned particles' ids (as a halo's do) elsewhere in the box, plus
// ghosts whose id nobody wrote (below first_id and past the set's ids), one outside the box and
// one with a NaN coordinate. Each bucket must list exactly the brute-force order: ascending
// (id, index), an id out of range as the set's id count. The list is in cell order exactly when
// that order is the identity, which it becomes once the particles are arranged by (bucket, id).
// With `corner`, the owned particles lie in the box's lower 0.2 … 0.6 along each axis (as a
// rank's share of the domain does): the owned view's table covers only their block of cells.
template <class T, int D, class P>
void check_id_order(P policy, Layout layout, OutsideParticles outside, bool corner = false) {
  SCOPED_TRACE(std::string(to_string(layout)) + ", " + std::to_string(D) + "D, " +
               (sizeof(T) == 4 ? "float" : "double") + (outside == OutsideParticles::flag ? ", flag" : ", clamp") +
               (corner ? ", owned in a corner" : ""));
  const Scenario<T, D> s = make_scenario<T, D>(layout);
  const Index owned = s.positions.size();
  const std::uint64_t first_id = 1000;
  ParticleSet set("Water", owned, 0, first_id);
  DiscreteVariable<Vec<T, D>>& x = set.add_variable(position_tag<T, D>, sortable_output_variable);
  std::mt19937_64 rng(11 + owned);
  std::vector<Vec<T, D>> positions = s.positions;
  if (corner)
    for (Vec<T, D>& p : positions)
      for (int a = 0; a < D; ++a)
        p[a] = s.box.lower[a] + (s.box.upper[a] - s.box.lower[a]) * (T(0.2) + T(0.4) * (p[a] - s.box.lower[a]) /
                                                                                   (s.box.upper[a] - s.box.lower[a]));
  std::vector<std::uint64_t> ids(owned);
  std::iota(ids.begin(), ids.end(), first_id);
  std::shuffle(ids.begin(), ids.end(), rng);
  const Index copies = owned / 5;
  for (Index g = 0; g < copies; ++g) {
    positions.push_back(random_point<T, D>(rng, 0, 1));
    ids.push_back(ids[(g * 7) % owned]);
  }
  const T nan = std::numeric_limits<T>::quiet_NaN();
  const std::uint64_t unwritten[] = {0, first_id + owned + 5, first_id + owned, first_id - 1};
  for (std::uint64_t id : unwritten) {
    positions.push_back(random_point<T, D>(rng, 0, 1));
    ids.push_back(id);
  }
  positions.push_back(Vec<T, D>::constant(T(2)));
  ids.push_back(ids[0]);
  Vec<T, D> with_nan = Vec<T, D>::constant(T(0.5));
  with_nan[0] = nan;
  positions.push_back(with_nan);
  ids.push_back(first_id + owned - 1);
  const Index n = positions.size();
  set.set_ghost_count(n - owned);

  CellLinkedList<T, D> cells(x, s.box, s.cutoff, outside);
  cells.order_within_cells_by_id(set);
  cells.keep_owned_view(set);
  EXPECT_TRUE(cells.orders_within_cells_by_id());
  const SearchGrid<T, D> grid = cells.grid();
  auto bucket_of = [&](const Vec<T, D>& p) {
    const CellPlacement<D> c = grid.place(p);
    return outside == OutsideParticles::flag && c.status != placement_inside ? grid.cell_count()
                                                                              : Index(grid.linear_index(c.cell));
  };
  // The reference: every particle's (bucket, id clamped to the set's range, index), sorted.
  auto reference = [&]() {
    std::vector<std::tuple<Index, std::uint64_t, std::uint32_t>> order;
    for (Index i = 0; i < n; ++i) {
      const std::uint64_t id = ids[i] - first_id;
      order.emplace_back(bucket_of(positions[i]), id < std::uint64_t(owned) ? id : std::uint64_t(owned),
                         std::uint32_t(i));
    }
    std::sort(order.begin(), order.end());
    return order;
  };
  // 2: the owned particles (the first `owned`) sorted by (bucket, id), the ghosts after them
  // not, as on several ranks: the list is not the identity, the owned view is.
  for (int arrangement = 0; arrangement < 3; ++arrangement) {
    SCOPED_TRACE(arrangement == 0 ? "shuffled" : arrangement == 1 ? "arranged by (bucket, id)" : "owned ones arranged");
    if (arrangement == 2) {
      std::reverse(positions.begin() + owned, positions.end());
      std::reverse(ids.begin() + owned, ids.end());
    }
    if (arrangement == 1) {  // the particles moved into the reference order: the identity
      const auto order = reference();
      std::vector<Vec<T, D>> p2;
      std::vector<std::uint64_t> id2;
      for (const auto& o : order) {
        p2.push_back(positions[std::get<2>(o)]);
        id2.push_back(ids[std::get<2>(o)]);
      }
      positions = p2;
      ids = id2;
    }
    x.assign(positions);
    set.ids().assign(ids);
    const auto order = reference();
    std::vector<std::uint32_t> expected_particles;
    std::vector<std::uint32_t> expected_offsets(cells.cell_count() + 2, 0);
    for (const auto& o : order) {
      expected_particles.push_back(std::get<2>(o));
      ++expected_offsets[std::get<0>(o) + 1];
    }
    std::partial_sum(expected_offsets.begin(), expected_offsets.end(), expected_offsets.begin());
    bool identity = true;
    for (Index k = 0; k < n; ++k) identity = identity && expected_particles[k] == k;
    EXPECT_EQ(identity, arrangement == 1);
    // The owned view: the first `owned` particles' cells in order, where their keys ascend, in
    // a table over the block of cells that holds them.
    Vec<int, D> first = grid.cells, last{};
    for (Index i = 0; i < owned; ++i)
      for (int a = 0; a < D; ++a) {
        first[a] = std::min(first[a], grid.place(positions[i]).cell[a]);
        last[a] = std::max(last[a], grid.place(positions[i]).cell[a]);
      }
    if (owned == 0) first = last = Vec<int, D>{};  // no owned particle: one cell
    const SearchGrid<T, D> block = grid.sub_grid(first, last);
    if (corner && arrangement == 0 && owned > 1) {  // (later arrangements mix the ghosts in)
      EXPECT_LT(block.cell_count() * 4, grid.cell_count()) << "the block is not a corner's";
    }
    auto block_bucket_of = [&](const Vec<T, D>& p) {
      const CellPlacement<D> c = block.place(p);
      return outside == OutsideParticles::flag && c.status != placement_inside ? block.cell_count()
                                                                                : Index(block.linear_index(c.cell));
    };
    bool owned_ascend = true;
    std::vector<std::uint32_t> expected_owned_offsets(block.cell_count() + 2, 0);
    for (Index i = 0; i < owned; ++i) {
      ++expected_owned_offsets[block_bucket_of(positions[i]) + 1];
      EXPECT_EQ(block.place(positions[i]).cell + first, grid.place(positions[i]).cell) << "particle " << i;
      if (i > 0) {
        const auto key = [&](Index k) {
          const std::uint64_t id = ids[k] - first_id;
          return std::pair(bucket_of(positions[k]), id < std::uint64_t(owned) ? id : std::uint64_t(owned));
        };
        owned_ascend = owned_ascend && !(key(i) < key(i - 1));
      }
    }
    std::partial_sum(expected_owned_offsets.begin(), expected_owned_offsets.end(), expected_owned_offsets.begin());
    if (arrangement != 0) {  // shuffled: seldom (one particle: always)
      EXPECT_TRUE(owned_ascend);
    }
    for (int build = 0; build < 2; ++build) {  // a rebuild starts clean
      cells.store_positions_in_cell_order(build == 1);
      cells.sort_only_ghosts(build == 0);  // where the owned ones ascend: merged, then every key sorted
      cells.build(policy);
      EXPECT_EQ(cells.offsets().to_vector(), expected_offsets);
      const auto particles = cells.particles().to_vector();
      EXPECT_EQ(particles, expected_particles);
      const CellListReport r = cells.report();
      EXPECT_EQ(r.in_cell_order, identity);
      EXPECT_EQ(r.out_of_box, 1u);
      EXPECT_EQ(r.non_finite, 1u);
      EXPECT_EQ(r.flagged, outside == OutsideParticles::flag ? 2u : 0u);
      ASSERT_EQ(cells.owned_view_ready(), owned_ascend);
      if (owned_ascend) {
        const CellListView<T, D> view = cells.owned_view(seq);
        EXPECT_TRUE(view.in_cell_order());
        EXPECT_TRUE(view.run_end.empty());
        EXPECT_EQ(std::vector<std::uint32_t>(view.offsets.begin(), view.offsets.end()), expected_owned_offsets);
        EXPECT_EQ(view.grid.cells, block.cells);
        EXPECT_EQ(view.grid.first_cell, block.first_cell);
      } else {
        EXPECT_THROW(cells.owned_view(seq), Error);
      }
      if (build == 1 && !identity) {  // the cell-ordered copy follows the list's order
        const CellListView<T, D> view = cells.view(seq);
        Index wrong = 0;
        for (Index k = 0; k < n; ++k) {
          const Vec<T, D> a = view.points[k].position(), b = positions[particles[k]];
          for (int d = 0; d < D; ++d) wrong += !(a[d] == b[d] || (a[d] != a[d] && b[d] != b[d]));
        }
        EXPECT_EQ(wrong, 0u);
      }
    }
  }
}

TYPED_TEST(CellListBuild, OrderedByIdListsEachCellInAscendingId) {
  for (Layout layout : all_layouts)
    for (OutsideParticles outside : {OutsideParticles::clamp, OutsideParticles::flag}) {
      check_id_order<float, 2>(this->policy, layout, outside);
      check_id_order<double, 2>(this->policy, layout, outside);
      check_id_order<float, 3>(this->policy, layout, outside);
      check_id_order<double, 3>(this->policy, layout, outside);
    }
  check_id_order<float, 3>(this->policy, all_layouts[0], OutsideParticles::clamp, true);
  check_id_order<double, 2>(this->policy, all_layouts[0], OutsideParticles::flag, true);
}

TYPED_TEST(CellListBuild, OrderedByIdRefusesAnotherSetsIds) {
  ParticleSet set("Water", 3);
  DiscreteVariable<Vec<double, 2>> x("Position", 4);
  CellLinkedList<double, 2> cells(x, {Vec<double, 2>{}, Vec<double, 2>::constant(1.0)}, 0.25);
  cells.order_within_cells_by_id(set);
  EXPECT_THROW(cells.build(this->policy), Error);
}

// After the positions moved: the lists are kept exactly where every particle stays in its
// bucket (and then equal a fresh build's, the cell-ordered positions refreshed), and refused
// where one crossed a cell face, left the box of a flagging list, or became NaN.
TYPED_TEST(CellListBuild, KeptAfterAMoveOnlyWhereEveryParticleStaysInItsCell) {
  const auto policy = this->policy;
  for (OutsideParticles outside : {OutsideParticles::clamp, OutsideParticles::flag}) {
    SCOPED_TRACE(outside == OutsideParticles::clamp ? "clamp" : "flag");
    const Scenario<double, 2> s = make_scenario<double, 2>(Layout::random);
    ParticleSet set("Wall", s.positions.size());
    DiscreteVariable<Vec<double, 2>> x("Position");
    x.assign(s.positions);
    CellLinkedList<double, 2> cells(x, s.box, s.cutoff, outside);
    cells.order_within_cells_by_id(set);
    cells.store_positions_in_cell_order();
    EXPECT_FALSE(cells.keep_if_cells_unchanged(policy));  // never built
    cells.build(policy);
    EXPECT_TRUE(cells.keep_if_cells_unchanged(policy));  // not moved
    // Each particle moved a quarter of the way to its cell's centre: the same cells.
    std::vector<Vec<double, 2>> moved = s.positions;
    for (Vec<double, 2>& p : moved) {
      const Vec<int, 2> c = cells.grid().place(p).cell;
      for (int a = 0; a < 2; ++a) {
        const double centre = s.box.lower[a] + (c[a] + 0.5) * cells.grid().axis_cell_size[a];
        p[a] += 0.25 * (centre - p[a]);
      }
    }
    x.assign(moved);
    const std::uint64_t builds = cells.builds();
    ASSERT_TRUE(cells.keep_if_cells_unchanged(policy));
    EXPECT_EQ(cells.builds(), builds);
    const auto kept = cells.particles().to_vector();
    const CellListView<double, 2> view = cells.view(seq);
    std::vector<Vec<double, 2>> kept_points;
    for (Index k = 0; k < view.points.size(); ++k) kept_points.push_back(view.points[k].position());
    cells.build(policy);
    EXPECT_EQ(cells.particles().to_vector(), kept);
    const CellListView<double, 2> fresh = cells.view(seq);
    ASSERT_EQ(fresh.points.size(), kept_points.size());
    for (Index k = 0; k < fresh.points.size(); ++k) EXPECT_EQ(fresh.points[k].position(), kept_points[k]) << k;
    // One particle over a cell face, one out of the box, one NaN: each alone is a change.
    const double h = moved[3][0] > 0.5 ? -cells.grid().axis_cell_size[0] : cells.grid().axis_cell_size[0];
    for (const Vec<double, 2>& q : {Vec<double, 2>{{moved[3][0] + h, moved[3][1]}}, Vec<double, 2>{{-0.5, moved[3][1]}},
                                    Vec<double, 2>{{std::numeric_limits<double>::quiet_NaN(), 0.5}}}) {
      std::vector<Vec<double, 2>> one = moved;
      one[3] = q;
      x.assign(one);
      const bool same_bucket = q[0] < 0 && outside == OutsideParticles::clamp &&
                               cells.grid().place(q).cell == cells.grid().place(moved[3]).cell;
      EXPECT_EQ(cells.keep_if_cells_unchanged(policy), same_bucket) << q[0];
    }
  }
}

TEST(HostSearchGrid, GeometryAndErrors) {
  using G = SearchGrid<double, 2>;
  const Box<double, 2> unit{Vec<double, 2>{}, Vec<double, 2>::constant(1.0)};
  const G g = G::make(unit, 0.25);
  EXPECT_EQ(g.cells, (Vec<int, 2>{{5, 5}}));  // faces at 0, .25, .5, .75, 1: the face at 1 is in cell 4
  EXPECT_EQ(g.place({{0.25, 0.5}}).cell, (Vec<int, 2>{{1, 2}}));
  EXPECT_EQ(g.place({{-0.1, 0.5}}).status, placement_out_of_box);
  EXPECT_EQ(g.place({{-0.1, 0.5}}).cell[0], 0);
  EXPECT_EQ(g.place({{std::numeric_limits<double>::infinity(), 0.5}}).cell[0], 4);
  EXPECT_EQ(G::make(unit, 0.25, 0.5).cells, (Vec<int, 2>{{3, 3}}));
  EXPECT_EQ(G::make(unit, 0.25).reach, 1);
  EXPECT_EQ(G::make(unit, 0.25, 0.2).reach, 2);       // cells smaller than the cutoff: a wider stencil
  EXPECT_EQ(G::make(unit, 0.25, 0.0625).reach, 4);
  EXPECT_THROW(G::make(unit, 0.25, 0.06), Error);     // below cutoff / SearchGrid::max_reach
  EXPECT_THROW(G::make(unit, 0.0), Error);
  EXPECT_THROW(G::make(unit, std::numeric_limits<double>::quiet_NaN()), Error);
  EXPECT_THROW(G::make({Vec<double, 2>::constant(1.0), Vec<double, 2>{}}, 0.1), Error);  // empty box
  EXPECT_THROW(G::make(unit, 1e-7), Error);  // 10^7 cells per axis > 2^21
  EXPECT_NO_THROW(G::make({Vec<double, 2>{}, Vec<double, 2>{{1.0, 1e-6}}}, 1.0 / 2000000));  // 2000001 cells
  EXPECT_THROW((SearchGrid<double, 3>::make({Vec<double, 3>{}, Vec<double, 3>::constant(1.0)}, 5e-4)), Error);  // 2001^3 > 2^32 cells
}

// A block of a grid's cells places every position in the whole grid's cell less the block's
// first (outside the block too: a walk from there visits the whole grid's cells that lie in the
// block), with the cell coordinate less that integer exactly.
TEST(HostSearchGrid, SubGridPlacesAsTheWholeGrid) {
  using G = SearchGrid<float, 3>;
  const G g = G::make({Vec<float, 3>{{-1.3f, 0.0f, 2.0f}}, Vec<float, 3>{{7.1f, 0.4f, 9.0f}}}, 0.013f, 0.0065f);
  const Vec<int, 3> first{{100, 3, 400}}, last{{900, 50, 700}};
  const G b = g.sub_grid(first, last);
  EXPECT_EQ(b.cells, (Vec<int, 3>{{801, 48, 301}}));
  EXPECT_EQ(b.first_cell, first);
  EXPECT_EQ(b.sub_grid(Vec<int, 3>{{1, 0, 0}}, Vec<int, 3>{{1, 0, 0}}).first_cell, (Vec<int, 3>{{101, 3, 400}}));
  std::mt19937_64 rng(5);
  Index inside = 0;
  for (int k = 0; k < 200000; ++k) {
    Vec<float, 3> x;
    for (int a = 0; a < 3; ++a)
      x[a] = std::uniform_real_distribution<float>(g.box.lower[a], g.box.upper[a])(rng);
    const Vec<int, 3> whole = g.place(x).cell;
    bool in = true;
    for (int a = 0; a < 3; ++a) in = in && first[a] <= whole[a] && whole[a] <= last[a];
    const Vec<int, 3> c = b.place(x).cell;
    for (int a = 0; a < 3; ++a) {
      ASSERT_EQ(b.cell_coordinate(x, a), g.cell_coordinate(x, a) - float(first[a])) << k;
      ASSERT_EQ(c[a] + first[a], whole[a]) << k;
    }
    inside += in;
  }
  EXPECT_GT(inside, 1000u);
  // Cell faces: the whole grid's placement at a face is the block's.
  for (int i = first[0]; i <= last[0]; i += 37) {
    Vec<float, 3> x{{g.box.lower[0] + float(i) * g.cell_size, 0.2f, 5.0f}};
    ASSERT_EQ(b.place(x).cell[0] + first[0], g.place(x).cell[0]) << i;
  }
  // Beyond the whole grid: clamped into it, as the whole grid places it.
  const Vec<float, 3> far{{100.0f, -5.0f, 5.0f}};
  EXPECT_EQ(b.place(far).cell + first, g.place(far).cell);
  EXPECT_EQ(b.place(far).status, placement_out_of_box);
  EXPECT_THROW(g.sub_grid(Vec<int, 3>{{0, 0, 0}}, Vec<int, 3>{{g.cells[0], 0, 0}}), Error);
  EXPECT_THROW(g.sub_grid(Vec<int, 3>{{5, 0, 0}}, Vec<int, 3>{{4, 0, 0}}), Error);
  // Periodic axes stay whole.
  const G p = G::make_periodic(g.box, 0.013f, {true, false, false}, 0.0065f);
  EXPECT_EQ(p.sub_grid(first, last).cells[0], p.cells[0]);
  EXPECT_EQ(p.sub_grid(first, last).first_cell[0], 0);
}

}  // namespace
