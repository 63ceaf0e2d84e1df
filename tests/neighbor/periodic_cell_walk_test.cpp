// Periodic boundaries by wrapped cell indices (neighbor/periodic_cell_list.hpp,
// neighbor/periodic_cell_walk.hpp), on every policy, 2D and 3D, float and double, with one, two
// or all axes periodic:
//   * the neighbours the walk finds are the brute-force minimum-image neighbours: the same
//     particles, each once, r_ij the minimum-image displacement within 8 ulps of the coordinates;
//     in boxes that are not cubes, with cells of the cutoff, cutoff / 2 and cutoff / 4, in a box
//     exactly 2 reach + 1 cells wide along axes 0 and D - 1, and in one exactly two cutoffs wide
//     there (fewer cells than the stencil: a row meets cells twice, with different shifts); through
//     the CSR indices, with the particles in cell order, through the cell-ordered position copy,
//     and from another set's positions (contact);
//   * on a lattice whose arithmetic is exact, every particle has 8 (2D) or 26 (3D) neighbours
//     with all axes periodic, r_ij exactly the minimum image, and walks the same number of
//     candidates wherever it is;
//   * SearchGrid::make_periodic divides periodic axes exactly and leaves the others as make();
//   * wrap() gives PeriodicImages::wrap's bits; a box narrower than two cutoffs is one Error line.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "neighbor/minimum_image_reference.hpp"
#include "support/policy_test.hpp"
#include "unisph/neighbor/periodic_cell_list.hpp"
#include "unisph/particles/body.hpp"

namespace {
using namespace unisph;
using namespace unisph::testing;

// The neighbours of the sources in the cell list's order (PeriodicCellWalk::cell_order_source),
// in rows by particle index.
template <class T, int D>
struct CollectInCellOrder {
  PeriodicCellWalk<T, D> walk;
  Index capacity;
  View<std::uint32_t> found;
  View<Vec<T, D>> displacement;
  View<std::uint32_t> counts;
  UNISPH_HOST_DEVICE void operator()(Index k) const {
    const CellOrderSource s = walk.cell_order_source(k);
    const Index i = s.particle;
    Index c = 0;
    walk.for_each_neighbor(s, [&](Index j, const NeighborPair<T, D>& pair) {
      if (c < capacity) {
        found[i * capacity + c] = static_cast<std::uint32_t>(j);
        displacement[i * capacity + c] = pair.r_ij;
      }
      ++c;
    });
    counts[i] = static_cast<std::uint32_t>(c);
  }
};

template <class T, int D, class P>
std::vector<std::vector<Found<T, D>>> collect_in_cell_order(P policy, const PeriodicCellWalk<T, D>& walk, Index n,
                                                            Index capacity) {
  DiscreteVariable<std::uint32_t> found("found", n * capacity), counts("counts", n);
  DiscreteVariable<Vec<T, D>> r("r", n * capacity);
  particle_for(policy, n,
               CollectInCellOrder<T, D>{walk, capacity, found.write(policy), r.write(policy), counts.write(policy)});
  const std::vector<std::uint32_t> f = found.to_vector(), c = counts.to_vector();
  const std::vector<Vec<T, D>> d = r.to_vector();
  std::vector<std::vector<Found<T, D>>> out(n);
  for (Index i = 0; i < n; ++i) {
    EXPECT_LE(c[i], capacity) << "source " << i << " has more neighbours than any reference row";
    for (Index k = 0; k < std::min<Index>(c[i], capacity); ++k) out[i].push_back({f[i * capacity + k], d[i * capacity + k]});
  }
  return out;
}

template <class T, int D>
struct CountCandidates {
  PeriodicCellWalk<T, D> walk;
  View<std::uint32_t> counts;
  UNISPH_HOST_DEVICE void operator()(Index i) const { counts[i] = static_cast<std::uint32_t>(walk.candidate_count(i)); }
};

enum class Width { plain, stencil, two_cutoffs };

// A box that is not a cube and does not start at the origin (binary fractions: exact in float).
// Along axes 0 and D - 1, `stencil` makes it exactly 2 reach + 1 cells of cutoff / split wide,
// `two_cutoffs` exactly two cutoffs (the narrowest allowed).
template <class T, int D>
Box<T, D> walk_box(Width width, T cutoff, int split) {
  Box<T, D> box;
  const double lower[3] = {-0.375, 0.25, 1.0}, extent[3] = {1.0, 0.75, 0.5};
  for (int a = 0; a < D; ++a) {
    double e = extent[a];
    if (a == 0 || a == D - 1) {
      if (width == Width::stencil) e = double(2 * split + 1) * double(cutoff) / split;
      if (width == Width::two_cutoffs) e = 2 * double(cutoff);
    }
    box.lower[a] = T(lower[a]);
    box.upper[a] = T(lower[a] + e);
  }
  return box;
}

const char* name_of(Width w) {
  return w == Width::plain ? "" : (w == Width::stencil ? ", 2 reach + 1 cells wide" : ", two cutoffs wide");
}

// The order that sorts the positions by their cell in `grid` (cell order: the build detects it).
template <class T, int D>
std::vector<std::uint32_t> cell_order(const std::vector<Vec<T, D>>& x, const SearchGrid<T, D>& grid) {
  std::vector<std::uint32_t> order(x.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return grid.linear_index(grid.place(x[a]).cell) < grid.linear_index(grid.place(x[b]).cell);
  });
  return order;
}

template <class T, int D, class P>
void check_minimum_image(P policy) {
  const T cutoff = T(0.125);
  for (Width width : {Width::plain, Width::stencil, Width::two_cutoffs})
    for (std::array<bool, D> periodic : axis_choices<T, D>())
      for (int split : {1, 2, 4}) {
        SCOPED_TRACE((describe<T, D>(periodic)) + name_of(width) + ", cells of cutoff / " + std::to_string(split));
        const Box<T, D> box = walk_box<T, D>(width, cutoff, split);
        const Index n = D == 2 ? 600 : 1500;
        std::vector<Vec<T, D>> x = random_positions(box, n, 17 + split + 3 * D);
        // On the upper faces too (the same points as the lower faces along periodic axes).
        x[8] = box.upper;
        x[9][0] = box.upper[0];
        x[10][D - 1] = box.upper[D - 1];
        const T cell = cutoff / T(split);  // exact: split is a power of two
        const double tol = coordinate_tolerance(box);
        const auto ref = minimum_image<T, D>(x, x, box, periodic, cutoff, true, tol);
        Index capacity = 1;
        for (const auto& r : ref) capacity = std::max<Index>(capacity, r.size() + 1);
        Index pairs = 0;

        Body<T, D> body("Fluid", box, n);
        body.positions().assign(x);
        PeriodicCellList<T, D> cells(body.positions(), box, periodic, cutoff, OutsideParticles::flag, cell);
        const SearchGrid<T, D>& grid = cells.grid();
        ASSERT_EQ(grid.reach, split);
        for (int a = 0; a < D; ++a)
          if (periodic[a] && (a == 0 || a == D - 1) && width != Width::plain) {
            EXPECT_EQ(grid.cells[a], 2 * grid.reach + (width == Width::stencil ? 1 : 0)) << "axis " << a;
          }
        cells.wrap(policy);
        cells.build(policy);
        const CellListReport report = cells.cells().report();
        EXPECT_EQ(report.out_of_box, 0u);
        EXPECT_FALSE(report.in_cell_order);
        const Index indexed_bad = compare<T, D>(collect(policy, cells.inner_walk(policy), n, capacity, {}, n), ref, tol, pairs);
        EXPECT_EQ(indexed_bad, 0u) << "through the CSR indices";
        EXPECT_GT(pairs, Index(n) * (D == 2 ? 5 : 10));

        // The cell-ordered copy of the positions, sources in the list's order.
        cells.cells().store_positions_in_cell_order();
        cells.build(policy);
        const Index copy_bad =
            compare<T, D>(collect_in_cell_order(policy, cells.inner_walk(policy), n, capacity), ref, tol, pairs);
        EXPECT_EQ(copy_bad, 0u) << "through the cell-ordered copy";

        // The particles in cell order: contiguous candidates (found rows mapped back to x's indices).
        const std::vector<std::uint32_t> order = cell_order(x, grid);
        std::vector<Vec<T, D>> sorted(n);
        for (Index k = 0; k < n; ++k) sorted[k] = x[order[k]];
        Body<T, D> ordered("Ordered", box, n);
        ordered.positions().assign(sorted);
        PeriodicCellList<T, D> sorted_cells(ordered.positions(), box, periodic, cutoff, OutsideParticles::clamp, cell);
        sorted_cells.build(policy);
        EXPECT_TRUE(sorted_cells.cells().report().in_cell_order);
        const auto in_order = collect(policy, sorted_cells.inner_walk(policy), n, capacity, {}, n);
        std::vector<std::vector<Found<T, D>>> mapped(n);
        for (Index k = 0; k < n; ++k)
          for (const Found<T, D>& f : in_order[k]) mapped[order[k]].push_back({order[f.source], f.r});
        const Index ordered_bad = compare<T, D>(mapped, ref, tol, pairs);
        EXPECT_EQ(ordered_bad, 0u) << "particles in cell order";

        // Another set's positions as sources.
        if (split != 4) {
          const std::vector<Vec<T, D>> y = random_positions(box, 200, 5);
          DiscreteVariable<Vec<T, D>> other("Other");
          other.assign(y);
          const auto cref = minimum_image<T, D>(y, x, box, periodic, cutoff, false, tol);
          Index cap = 1;
          for (const auto& r : cref) cap = std::max<Index>(cap, r.size() + 1);
          const Index contact_bad =
              compare<T, D>(collect(policy, cells.contact_walk(policy, other), y.size(), cap, {}, n), cref, tol, pairs);
          EXPECT_EQ(contact_bad, 0u) << "contact";
        }
      }
}

// The lattice 0, 1/16, ..., 15/16 along each axis in [0, 1), all axes periodic, cutoff 1/8:
// every sum is exact, pairs at exactly the cutoff are out, so every particle has the 8 (2D) or
// 26 (3D) lattice neighbours, r_ij exactly the minimum image, and walks the same candidates
// (2^D per cell, 3^D cells) wherever it lies.
template <class T, int D, class P>
void check_lattice(P policy) {
  const int side = 16;
  Index n = 1;
  for (int a = 0; a < D; ++a) n *= side;
  std::vector<Vec<T, D>> x(n);
  for (Index k = 0; k < n; ++k) {
    Index r = k;
    for (int a = 0; a < D; ++a, r /= side) x[k][a] = T(r % side) / T(side);
  }
  const Box<T, D> box{Vec<T, D>::constant(T(0)), Vec<T, D>::constant(T(1))};
  std::array<bool, D> periodic;
  periodic.fill(true);
  Body<T, D> body("Lattice", box, n);
  body.positions().assign(x);
  PeriodicCellList<T, D> cells(body.positions(), box, periodic, T(0.125));
  for (int a = 0; a < D; ++a) EXPECT_EQ(cells.grid().cells[a], 8);
  cells.build(policy);
  const auto found = collect(policy, cells.inner_walk(policy), n, 40, {}, n);
  const auto ref = minimum_image<T, D>(x, x, box, periodic, T(0.125), true, 0.0);
  Index pairs = 0;
  const Index bad = compare<T, D>(found, ref, 0.0, pairs);
  EXPECT_EQ(bad, 0u);
  EXPECT_EQ(pairs, n * (D == 2 ? 8 : 26));
  for (const auto& f : found) EXPECT_EQ(f.size(), D == 2 ? 8u : 26u);
  DiscreteVariable<std::uint32_t> counts("counts", n);
  particle_for(policy, n, CountCandidates<T, D>{cells.inner_walk(policy), counts.write(policy)});
  const std::vector<std::uint32_t> c = counts.to_vector();
  const std::uint32_t expected = D == 2 ? 36u : 216u;
  EXPECT_EQ(std::count(c.begin(), c.end(), expected), std::ptrdiff_t(n)) << "candidates per particle";
}

template <class T, int D, class P>
void check_wrap(P policy) {
  const Box<T, D> box = walk_box<T, D>(Width::plain, T(0.125), 1);
  std::array<bool, D> periodic{};
  periodic[0] = true;
  periodic[D - 1] = true;
  const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
  std::vector<Vec<T, D>> x = random_positions(box, 400, 9);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> far(-3.0, 3.0);
  for (std::size_t k = 20; k < 300; ++k)
    for (int a = 0; a < D; ++a) x[k][a] = T(box.lower[a] + far(rng) * (box.upper[a] - box.lower[a]));
  x[300][0] = box.upper[0];
  x[301][0] = std::nextafter(box.lower[0], -inf);
  x[302][0] = nan;
  x[303][0] = inf;
  Body<T, D> body("Fluid", box, x.size());
  body.positions().assign(x);
  PeriodicCellList<T, D> cells(body.positions(), box, periodic, T(0.125));
  cells.wrap(policy);
  Body<T, D> again("Fluid", box, x.size());
  again.positions().assign(x);
  PeriodicImages<T, D>(again.particles(), again.positions(), box, periodic, T(0.125)).wrap(seq);
  const std::vector<Vec<T, D>> y = body.positions().to_vector(), z = again.positions().to_vector();
  EXPECT_TRUE(std::memcmp(z.data(), y.data(), y.size() * sizeof(Vec<T, D>)) == 0);
  for (std::size_t k = 0; k < 300; ++k)
    for (int a = 0; a < D; ++a)
      if (periodic[a]) {
        EXPECT_GE(y[k][a], box.lower[a]);
        EXPECT_LE(y[k][a], box.upper[a]);
      }
}

UNISPH_POLICY_TEST_SUITE(PeriodicCellWalkTest);

TYPED_TEST(PeriodicCellWalkTest, MinimumImageNeighbors2D) {
  check_minimum_image<float, 2>(this->policy);
  check_minimum_image<double, 2>(this->policy);
}
TYPED_TEST(PeriodicCellWalkTest, MinimumImageNeighbors3D) {
  check_minimum_image<float, 3>(this->policy);
  check_minimum_image<double, 3>(this->policy);
}
TYPED_TEST(PeriodicCellWalkTest, LatticeHasEveryNeighborAcrossFacesEdgesAndCorners) {
  check_lattice<float, 2>(this->policy);
  check_lattice<double, 2>(this->policy);
  check_lattice<float, 3>(this->policy);
  check_lattice<double, 3>(this->policy);
}
TYPED_TEST(PeriodicCellWalkTest, WrapIsThatOfTheImages) {
  check_wrap<float, 2>(this->policy);
  check_wrap<double, 3>(this->policy);
}

TEST(HostPeriodicCellWalk, MakePeriodicDividesPeriodicAxesOnly) {
  const Box<double, 3> box{{{-0.375, 0.25, 1.0}}, {{0.625, 1.0, 1.3}}};
  const double cutoff = 0.125, cell = 0.07;
  const SearchGrid<double, 3> plain = SearchGrid<double, 3>::make(box, cutoff, cell);
  const SearchGrid<double, 3> wrapped = SearchGrid<double, 3>::make_periodic(box, cutoff, {true, false, true}, cell);
  EXPECT_EQ(plain.periodic_axes, 0u);
  EXPECT_EQ(wrapped.periodic_axes, 5u);
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(plain.axis_cell_size[a], plain.cell_size);
    EXPECT_EQ(plain.axis_inverse_cell_size[a], plain.inverse_cell_size);
    const double length = box.upper[a] - box.lower[a];
    EXPECT_EQ(plain.cells[a], int(std::floor(length / cell)) + 1) << "make() keeps its partial last cell";
    if (a == 1) {
      EXPECT_EQ(wrapped.cells[a], plain.cells[a]);
      EXPECT_EQ(wrapped.axis_cell_size[a], cell);
      continue;
    }
    EXPECT_EQ(wrapped.cells[a], int(std::floor(length / cell))) << "axis " << a;
    EXPECT_GE(wrapped.axis_cell_size[a], cell);
    EXPECT_NEAR(wrapped.axis_cell_size[a] * wrapped.cells[a], length, 1e-15);
    // The faces: the lower in cell 0, the upper in the last cell.
    Vec<double, 3> x = box.lower;
    EXPECT_EQ(wrapped.place(x).cell[a], 0);
    x[a] = box.upper[a];
    EXPECT_EQ(wrapped.place(x).cell[a], wrapped.cells[a] - 1);
    x[a] = std::nextafter(box.upper[a], 0.0);
    EXPECT_EQ(wrapped.place(x).cell[a], wrapped.cells[a] - 1);
  }
  EXPECT_EQ(wrapped.reach, plain.reach);
  EXPECT_EQ(wrapped.stencil_radius, plain.stencil_radius);
  // A box narrower than one cell along a periodic axis: one cell, the whole period.
  const Box<double, 2> thin{{{0, 0}}, {{0.05, 1}}};
  const SearchGrid<double, 2> one = SearchGrid<double, 2>::make_periodic(thin, 0.02, {true, false}, 0.08);
  EXPECT_EQ(one.cells[0], 1);
  EXPECT_EQ(one.axis_cell_size[0], 0.05);
}

TEST(HostPeriodicCellWalk, BoxNarrowerThanTwoCutoffsIsRefused) {
  const Box<double, 3> box{{{0, 0, 0}}, {{1, 0.2, 1}}};
  DiscreteVariable<Vec<double, 3>> x("Water.Position", 10);
  try {
    PeriodicCellList<double, 3> cells(x, box, {false, true, false}, 0.125);
    FAIL() << "a box 0.2 wide along a periodic axis with cutoff 0.125 was accepted";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_NE(what.find("PeriodicCellList of 'Water.Position'"), std::string::npos) << what;
    EXPECT_NE(what.find("periodic axis 1"), std::string::npos) << what;
    EXPECT_NE(what.find("narrower than two cutoffs"), std::string::npos) << what;
  }
  EXPECT_NO_THROW((PeriodicCellList<double, 3>(x, box, {true, false, true}, 0.125)));
  EXPECT_NO_THROW((PeriodicCellList<double, 3>(x, box, {true, true, true}, 0.1)));
}

}  // namespace
