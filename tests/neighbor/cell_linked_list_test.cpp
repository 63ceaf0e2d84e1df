// The cell linked list: CSR structure (every particle once, in the cell its position says),
// the same on every policy; the search grid's geometry and its errors.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "neighbor_scenarios.hpp"
#include "support/policy_test.hpp"
#include "unisph/neighbor/cell_linked_list.hpp"

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

}  // namespace
