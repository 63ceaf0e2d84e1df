// Neighbour iteration written with views (iter/neighbor_views.hpp) against the direct search of
// NeighborSearch: for every source particle, the same neighbours j in the same order with the
// same pair geometry, bit for bit, on every policy; over the layouts of the neighbour tests
// (random, a lattice on cell and box faces, clustered, one cell, one particle, none), particles
// in any order and in cell order, cells of the cutoff and of half of it (a 5^D block), outside
// particles clamped or flagged, an inner and a contact-like search. The pair count is also
// checked against brute force.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "neighbor/neighbor_scenarios.hpp"
#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/iter/neighbor_views.hpp"
#include "unisph/neighbor/inner_relation.hpp"

namespace {
using namespace unisph;
using unisph::testing::Layout;
namespace scenarios = unisph::testing;

// The reference: the direct search's row walk (consecutive CSR ranges per row of cells) with
// the cutoff test, written out here so that the test stays a comparison of the two walks
// whichever one NeighborSearch::for_each_direct_neighbor uses.
template <class T, int D, class F>
UNISPH_HOST_DEVICE void row_walk(const NeighborSearch<T, D>& search, Index i, F&& f) {
  search.for_each_direct_candidate(i, [&](Index j, const Vec<T, D>& xi, const Vec<T, D>& xj) {
    NeighborPair<T, D> pair;
    if (search.targets.grid.test_pair(xi, xj, pair.r_ij, pair.squared_distance)) {
      pair.complete();
      f(j, static_cast<const NeighborPair<T, D>&>(pair));
    }
  });
}

template <class T, int D>
struct CountPairs {
  NeighborSearch<T, D> search;
  View<std::uint32_t> direct, by_views;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    std::uint32_t n = 0, m = 0;
    row_walk(search, i, [&](Index, const NeighborPair<T, D>&) { ++n; });
    iter::for_each_neighbor(search, i, [&](Index, const NeighborPair<T, D>&) { ++m; });
    direct[i] = n;
    by_views[i] = m;
  }
};

template <class T, int D>
struct ListPairs {
  NeighborSearch<T, D> search;
  View<const std::uint64_t> offsets;
  View<std::uint32_t> j_direct, j_views;
  View<NeighborPair<T, D>> pair_direct, pair_views;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    std::uint64_t k = offsets[i];
    row_walk(search, i, [&](Index j, const NeighborPair<T, D>& pair) {
      j_direct[k] = std::uint32_t(j);
      pair_direct[k++] = pair;
    });
    k = offsets[i];
    iter::for_each_neighbor(search, i, [&](Index j, const NeighborPair<T, D>& pair) {
      j_views[k] = std::uint32_t(j);
      pair_views[k++] = pair;
    });
  }
};

template <class T, int D, class P>
void check_same_pairs(P policy, Layout layout, bool cell_order, int split, OutsideParticles outside, bool inner) {
  unisph::testing::Scenario<T, D> s = unisph::testing::make_scenario<T, D>(layout);
  std::vector<Vec<T, D>> x = s.positions;
  // Particles outside the box: beyond the upper faces, below the lower ones, and a NaN.
  if (!x.empty()) {
    x.push_back(Vec<T, D>::constant(T(1.05)));
    x.push_back(Vec<T, D>::constant(T(-0.01)));
    Vec<T, D> nan = x[0];
    nan[D - 1] = std::numeric_limits<T>::quiet_NaN();
    x.push_back(nan);
  }
  DiscreteVariable<Vec<T, D>> positions("Positions");
  CellLinkedList<T, D> cells(positions, s.box, s.cutoff, outside, s.cutoff / T(split));
  if (cell_order) {
    const SearchGrid<T, D> grid = cells.grid();
    const auto key = [&](const Vec<T, D>& p) {
      const CellPlacement<D> c = grid.place(p);
      return outside == OutsideParticles::flag && c.status != placement_inside ? grid.cell_count()
                                                                                : grid.linear_index(c.cell);
    };
    std::stable_sort(x.begin(), x.end(), [&](const auto& a, const auto& b) { return key(a) < key(b); });
  }
  positions.assign(x);
  cells.build(policy);
  const std::string where = std::string(unisph::testing::to_string(layout)) + (cell_order ? ", cell order" : ", any order") +
                            ", cells of cutoff / " + std::to_string(split) +
                            (outside == OutsideParticles::flag ? ", outside flagged" : ", outside clamped") +
                            (inner ? ", inner" : ", contact");
  if (cell_order) {
    ASSERT_TRUE(cells.report().in_cell_order) << where;
  }

  InnerRelation<T, D> relation(cells, SearchMethod::direct);
  NeighborSearch<T, D> search = relation.direct_search(policy);
  // A contact-like search: the sources are other points (the targets shifted by a third of the
  // cutoff), so no j is skipped as i itself.
  DiscreteVariable<Vec<T, D>> shifted("Shifted");
  if (!inner) {
    std::vector<Vec<T, D>> y = x;
    for (auto& p : y) p[0] = p[0] + s.cutoff / T(3);
    shifted.assign(y);
    search.sources = shifted.read(policy);
    search.inner = false;
  }
  const Index n = x.size();
  DiscreteVariable<std::uint32_t> direct("direct", n), by_views("by_views", n);
  particle_for(policy, n, CountPairs<T, D>{search, direct.write(policy), by_views.write(policy)});
  const std::vector<std::uint32_t> nd = direct.to_vector(), nv = by_views.to_vector();
  ASSERT_EQ(nd, nv) << where << ": neighbour counts";

  std::vector<std::uint64_t> start(n + 1, 0);
  for (Index i = 0; i < n; ++i) start[i + 1] = start[i] + nd[i];
  if (split == 1 && (!inner || outside == OutsideParticles::clamp)) {
    // Brute force: every pair within the cutoff (clamped outside particles are found too; a NaN never).
    const std::vector<Vec<T, D>> src = inner ? x : shifted.to_vector();
    const SearchGrid<T, D> grid = cells.grid();
    std::uint64_t brute = 0;
    for (Index i = 0; i < n; ++i) {
      if (outside == OutsideParticles::flag && grid.place(src[i]).status != placement_inside && inner) continue;
      for (Index j = 0; j < n; ++j) {
        if (inner && i == j) continue;
        if (outside == OutsideParticles::flag && grid.place(x[j]).status != placement_inside) continue;
        Vec<T, D> r;
        T r2;
        if (grid.test_pair(src[i], x[j], r, r2)) ++brute;
      }
    }
    EXPECT_EQ(start[n], brute) << where << ": pairs against brute force";
  }
  const Index pairs = start[n];
  DiscreteVariable<std::uint64_t> offsets("offsets");
  offsets.assign(start);
  DiscreteVariable<std::uint32_t> jd("jd", pairs), jv("jv", pairs);
  DiscreteVariable<NeighborPair<T, D>> pd("pd", pairs), pv("pv", pairs);
  particle_for(policy, n,
               ListPairs<T, D>{search, offsets.read(policy), jd.write(policy), jv.write(policy), pd.write(policy),
                               pv.write(policy)});
  const std::vector<std::uint32_t> hjd = jd.to_vector(), hjv = jv.to_vector();
  ASSERT_EQ(hjd, hjv) << where << ": neighbour lists";
  const std::vector<NeighborPair<T, D>> hpd = pd.to_vector(), hpv = pv.to_vector();
  for (Index k = 0; k < pairs; ++k)
    ASSERT_EQ(std::memcmp(&hpd[k], &hpv[k], sizeof(NeighborPair<T, D>)), 0) << where << ": the geometry of pair " << k;
}

template <class T, int D, class P>
void check_all(P policy) {
  for (Layout layout : unisph::testing::all_layouts)
    for (bool cell_order : {false, true})
      for (int split : {1, 2})
        for (OutsideParticles outside : {OutsideParticles::clamp, OutsideParticles::flag})
          for (bool inner : {true, false}) check_same_pairs<T, D>(policy, layout, cell_order, split, outside, inner);
}

UNISPH_POLICY_TEST_SUITE(NeighborViews);

TYPED_TEST(NeighborViews, SamePairsAsTheDirectSearch3DFloat) { check_all<float, 3>(this->policy); }
TYPED_TEST(NeighborViews, SamePairsAsTheDirectSearch2DDouble) { check_all<double, 2>(this->policy); }

}  // namespace
