// Neighbour iteration written with views (iter/neighbor_views.hpp, the engine's direct search)
// against the hand-written row walk it replaced: for every source particle, the same neighbours j in the same order with the
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
#include "unisph/neighbor/neighbor_views.hpp"
#include "unisph/neighbor/inner_relation.hpp"

namespace {
using namespace unisph;
using unisph::testing::Layout;
namespace scenarios = unisph::testing;

// The reference: the row walk the direct search ran before it was written with views (up to
// commit b717efc), kept here as a hand-written loop: per row of stencil cells one CSR range
// (consecutive cells of a row are consecutive places), the rows beyond the cutoff and the ends of
// each row trimmed with cells smaller than the cutoff, the cutoff test on each candidate. The
// engine (NeighborSearch::for_each_direct_neighbor, through iter::for_each_neighbor) must give
// the same pairs in the same order, bit for bit.
template <class T, int D>
struct RowWalk {
  const NeighborSearch<T, D>& search;

  UNISPH_HOST_DEVICE void axis_range(const Vec<int, D>& c, int a, bool trim, T t, T left2, int& first, int& last) const {
    const SearchGrid<T, D>& grid = search.targets.grid;
    first = c[a] - grid.reach > 0 ? c[a] - grid.reach : 0;
    last = c[a] + grid.reach < grid.cells[a] ? c[a] + grid.reach : grid.cells[a] - 1;
    if (trim) {
      const T half = std::sqrt(left2 > T(0) ? left2 : T(0));
      const T lo = std::floor(t - half), hi = std::floor(t + half);
      if (lo > T(first)) first = static_cast<int>(lo);
      if (hi < T(last)) last = static_cast<int>(hi);
    }
  }
  UNISPH_HOST_DEVICE static T gap_squared(bool trim, int k, T t) {
    if (!trim) return T(0);
    const T below = T(k) - t, above = t - T(k + 1);
    const T gap = below > T(0) ? below : (above > T(0) ? above : T(0));
    return gap * gap;
  }
  // g(begin, end) for the CSR range of each row of the stencil around x.
  template <class G>
  UNISPH_HOST_DEVICE void ranges(const Vec<T, D>& x, G&& g) const {
    const SearchGrid<T, D>& grid = search.targets.grid;
    const CellPlacement<D> placement = grid.place(x);
    if (placement.status & placement_non_finite) return;
    if (search.inner && search.targets.flag_outside && placement.status != placement_inside) return;
    const bool trim = grid.reach > 1 && placement.status == placement_inside;
    Vec<T, D> t;
    for (int a = 0; a < D; ++a) t[a] = trim ? grid.cell_coordinate(x, a) : T(0);
    const T radius2 = grid.stencil_radius * grid.stencil_radius;
    Vec<int, D> cell = placement.cell;
    const auto row = [&](T left2) {
      int first, last;
      axis_range(placement.cell, 0, trim, t[0], left2, first, last);
      cell[0] = first;
      const Index first_cell = grid.linear_index(cell);
      g(search.targets.offsets[first_cell], search.targets.offsets[first_cell + static_cast<Index>(last - first) + 1]);
    };
    int y_first, y_last;
    if constexpr (D == 2) {
      axis_range(placement.cell, 1, trim, t[1], radius2, y_first, y_last);
      for (int ky = y_first; ky <= y_last; ++ky) {
        cell[1] = ky;
        row(radius2 - gap_squared(trim, ky, t[1]));
      }
    } else {
      int z_first, z_last;
      axis_range(placement.cell, 2, trim, t[2], radius2, z_first, z_last);
      for (int kz = z_first; kz <= z_last; ++kz) {
        cell[2] = kz;
        const T left_z = radius2 - gap_squared(trim, kz, t[2]);
        axis_range(placement.cell, 1, trim, t[1], left_z, y_first, y_last);
        for (int ky = y_first; ky <= y_last; ++ky) {
          cell[1] = ky;
          row(left_z - gap_squared(trim, ky, t[1]));
        }
      }
    }
  }
};

template <class T, int D, class F>
UNISPH_HOST_DEVICE void row_walk(const NeighborSearch<T, D>& search, Index i, F&& f) {
  const Vec<T, D> xi = search.sources[i];
  const bool cell_order = search.targets.in_cell_order();
  RowWalk<T, D>{search}.ranges(xi, [&](std::uint32_t begin, std::uint32_t end) {
    for (std::uint32_t k = begin; k < end; ++k) {
      const Index j = cell_order ? Index(k) : Index(search.targets.particles[k]);
      if (search.inner && j == i) continue;
      NeighborPair<T, D> pair;
      if (search.targets.grid.test_pair(xi, search.targets.positions[j], pair.r_ij, pair.squared_distance)) {
        pair.complete();
        f(j, static_cast<const NeighborPair<T, D>&>(pair));
      }
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
