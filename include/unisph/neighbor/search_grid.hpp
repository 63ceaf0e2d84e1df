#pragma once
// SearchGrid<T, D>: the cell geometry of a neighbour search and its two decisions — which
// cell a position falls in, and whether two positions are within the cutoff. Every policy,
// the brute-force reference in the tests and the Morton keys use these functions, and they
// compute with unisph::uncontracted arithmetic, so that all of them decide every pair and
// every particle alike (see uncontracted_arithmetic.hpp).
//
// Cells are cubes of edge cell_size >= cutoff / max_reach. Every neighbour of a particle lies
// within `reach` = ceil(cutoff / cell_size) cells of its own along each axis (1 for the
// default cell_size = cutoff: the 3^D cells around it). Smaller cells walk fewer candidates
// when the search skips the cells beyond the cutoff (neighbor_search.hpp). Axis 0 runs
// fastest in the linear cell index, so the cells of a row along axis 0 are consecutive.
//
// make() covers the box with cubic cells, the last one along each axis partial (the upper face
// lies in it). make_periodic() is the option for wrapped cell indices (periodic_cell_walk.hpp):
// along the axes it is told are periodic the cells divide the box exactly (cells of edge
// L / floor(L / cell_size), no partial cell), so that cell cells[a] is cell 0 one period on.
// Other axes, and every axis of make(), keep the cubic cells: place() then computes exactly what
// it computed before the option existed (axis_inverse_cell_size[a] == inverse_cell_size).
//
// sub_grid() is a block of another grid's cells: the same box, cell size and placement
// arithmetic, its cell 0 at the whole grid's first_cell. place() clamps into the whole grid and
// gives the cell in the block's coordinates, which lie outside the block for positions outside
// it (the stencil walks clamp their ranges into the block), and cell_coordinate() is the whole
// grid's less an integer, which is exact. So a cell list over the block (CellLinkedList's owned
// view on several ranks) lists the particles within it as the whole grid's list does, and a walk
// visits the whole grid's cells that lie in the block: the same candidates in the same order,
// from a table the block's size.

#include <array>
#include <cstdint>
#include <limits>
#include <string>

#include "unisph/core/error.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/core/box.hpp"
#include "unisph/core/uncontracted_arithmetic.hpp"

namespace unisph {

// Why a position is not plainly inside the box (bits of CellPlacement::status).
enum PlacementStatus : unsigned {
  placement_inside = 0,
  placement_out_of_box = 1,  // a finite coordinate (or an infinity) beyond a face of the box
  placement_non_finite = 2,  // a NaN coordinate
};

template <int D>
struct CellPlacement {
  Vec<int, D> cell;  // clamped into the grid: a border cell for positions outside the box
  unsigned status;   // PlacementStatus bits
};

template <class T, int D>
struct SearchGrid {
  static_assert(std::is_floating_point_v<T>, "SearchGrid positions are float or double.");
  static_assert(D == 2 || D == 3, "unisph neighbour search is for 2D and 3D.");

  // Morton keys interleave 21 bits per axis into 63 bits, so no axis may have more cells.
  static constexpr int max_cells_per_axis = 1 << 21;
  // The smallest cells are cutoff / max_reach (a stencil of (2 * max_reach + 1)^D cells).
  static constexpr int max_reach = 4;

  Box<T, D> box;
  T cutoff;
  T cutoff_squared;
  T cell_size;
  T inverse_cell_size;
  Vec<int, D> cells;  // per axis
  int reach;          // cells searched on each side: the smallest k with k * cell_size >= cutoff
  // The cutoff in cell units, padded for the rounding of cell coordinates: a cell farther
  // than this from a particle's cell coordinate (cell_coordinate) holds none of its neighbours.
  // In units of cell_size: along an axis make_periodic() divides exactly the cells are wider, so
  // the radius (and reach) are conservative there.
  T stencil_radius;
  // The cells' edge along each axis and its inverse: cell_size and inverse_cell_size, except
  // along the axes make_periodic() divides exactly (L_a / cells[a] >= cell_size).
  Vec<T, D> axis_cell_size;
  Vec<T, D> axis_inverse_cell_size;
  // Bit a: make_periodic() divided axis a exactly (0 for a grid of make()).
  unsigned periodic_axes;
  // The whole grid's coordinates of this grid's cell 0 and its cells per axis (sub_grid(); 0 and
  // `cells` for make()).
  Vec<int, D> first_cell;
  Vec<int, D> whole_cells;

  // The grid covering `box` with cells of `cell_size` (0: the cutoff). Throws unisph::Error
  // for an empty or non-finite box, a cutoff that is not positive, a cell size below
  // cutoff / max_reach, or more than 2^21 cells along an axis.
  static SearchGrid make(const Box<T, D>& box, T cutoff, T cell_size = T(0)) {
    if (cell_size == T(0)) cell_size = cutoff;
    if (!(cutoff > T(0)) || !(cutoff < std::numeric_limits<T>::infinity()))
      throw Error("SearchGrid: the cutoff is " + std::to_string(cutoff) + "; it must be positive and finite");
    if (!(cell_size * T(max_reach) >= cutoff) || !(cell_size < std::numeric_limits<T>::infinity()))
      throw Error("SearchGrid: the cell size " + std::to_string(cell_size) + " is smaller than the cutoff " +
                  std::to_string(cutoff) + " / " + std::to_string(max_reach) +
                  "; the search walks at most " + std::to_string(max_reach) + " cells on each side");
    SearchGrid g{};
    g.box = box;
    g.cutoff = cutoff;
    g.cutoff_squared = uncontracted::mul(cutoff, cutoff);
    g.cell_size = cell_size;
    g.inverse_cell_size = T(1) / cell_size;
    g.reach = 1;
    while (T(g.reach) * cell_size < cutoff) ++g.reach;
    for (int a = 0; a < D; ++a) {
      if (!(box.lower[a] <= box.upper[a]) || !(box.upper[a] - box.lower[a] < std::numeric_limits<T>::infinity()))
        throw Error("SearchGrid: the box " + to_string(box) + " is empty or not finite along axis " +
                    std::to_string(a));
      // The same arithmetic as place(), so that the upper face itself falls in the last cell.
      const T t = uncontracted::mul(uncontracted::sub(box.upper[a], box.lower[a]), g.inverse_cell_size);
      if (!(t < T(max_cells_per_axis)))
        throw Error("SearchGrid: the box " + to_string(box) + " needs more than 2^21 cells of size " +
                    std::to_string(cell_size) + " along axis " + std::to_string(a) +
                    " (Morton keys hold 21 bits per axis); use larger cells or a smaller box");
      g.cells[a] = static_cast<int>(t) + 1;
    }
    // Cell coordinates below 2^21 carry an absolute rounding error of a few ulps of the
    // largest; 8 of them plus a relative 1e-4 keep the cell skipping conservative.
    int most = 1;
    for (int a = 0; a < D; ++a) most = g.cells[a] > most ? g.cells[a] : most;
    g.stencil_radius = cutoff * g.inverse_cell_size * T(1.0001) + T(8) * T(most) * std::numeric_limits<T>::epsilon();
    Index total = 1;
    for (int a = 0; a < D; ++a) total *= static_cast<Index>(g.cells[a]);
    if (total >= Index(std::numeric_limits<std::uint32_t>::max()))
      throw Error("SearchGrid: the box " + to_string(box) + " needs " + std::to_string(total) +
                  " cells; cell lists index cells with 32 bits, use larger cells or a smaller box");
    g.axis_cell_size = Vec<T, D>::constant(g.cell_size);
    g.axis_inverse_cell_size = Vec<T, D>::constant(g.inverse_cell_size);
    g.periodic_axes = 0u;
    g.first_cell = Vec<int, D>{};
    g.whole_cells = g.cells;
    return g;
  }

  // The block of this grid's cells from `first` to `last` (inclusive, this grid's coordinates,
  // within it); a periodic axis is kept whole (its wrapped indices need every cell).
  SearchGrid sub_grid(const Vec<int, D>& first, const Vec<int, D>& last) const {
    SearchGrid g = *this;
    for (int a = 0; a < D; ++a) {
      if (is_periodic(a)) continue;
      if (!(0 <= first[a] && first[a] <= last[a] && last[a] < cells[a]))
        throw Error("SearchGrid::sub_grid: cells " + std::to_string(first[a]) + " to " + std::to_string(last[a]) +
                    " along axis " + std::to_string(a) + " are not within the grid's " + std::to_string(cells[a]));
      g.first_cell[a] = first_cell[a] + first[a];
      g.cells[a] = last[a] - first[a] + 1;
    }
    return g;
  }

  // make()'s grid, except along the axes with periodic[a]: there floor(L_a / cell_size) cells
  // (at least one) of edge L_a / cells[a] divide the box's length L_a = upper - lower exactly,
  // the upper face in the last cell. reach and stencil_radius are make()'s (conservative along
  // the wider cells). Throws what make() throws.
  static SearchGrid make_periodic(const Box<T, D>& box, T cutoff, const std::array<bool, D>& periodic,
                                  T cell_size = T(0)) {
    SearchGrid g = make(box, cutoff, cell_size);
    for (int a = 0; a < D; ++a) {
      if (!periodic[a]) continue;
      // make() set cells[a] = floor(t) + 1 with t = L_a / cell_size as place() computes it.
      const int n = g.cells[a] > 1 ? g.cells[a] - 1 : 1;
      const T length = uncontracted::sub(box.upper[a], box.lower[a]);
      g.cells[a] = n;
      g.axis_cell_size[a] = length / T(n);
      g.axis_inverse_cell_size[a] = T(n) / length;
      g.periodic_axes |= 1u << a;
    }
    g.whole_cells = g.cells;
    return g;
  }

  UNISPH_HOST_DEVICE bool is_periodic(int a) const { return (periodic_axes >> a) & 1u; }

  UNISPH_HOST_DEVICE Index cell_count() const {
    Index total = 1;
    for (int a = 0; a < D; ++a) total *= static_cast<Index>(cells[a]);
    return total;
  }

  // The cell of x, clamped into the grid (a sub-grid: into the whole grid, in the sub-grid's
  // coordinates), and whether x was outside the box or not finite (a NaN coordinate is placed in
  // cell 0 of the whole grid along its axis).
  UNISPH_HOST_DEVICE CellPlacement<D> place(const Vec<T, D>& x) const {
    CellPlacement<D> p{};
    for (int a = 0; a < D; ++a) {
      const T xa = x[a];
      if (!(xa == xa)) {
        p.status |= placement_non_finite;
        p.cell[a] = -first_cell[a];
        continue;
      }
      if (xa < box.lower[a] || xa > box.upper[a]) p.status |= placement_out_of_box;
      const T t = uncontracted::mul(uncontracted::sub(xa, box.lower[a]), axis_inverse_cell_size[a]);
      // Compared as floating point before the conversion, which is undefined out of range.
      p.cell[a] = (t < T(0) ? 0 : (t < T(whole_cells[a]) ? static_cast<int>(t) : whole_cells[a] - 1)) - first_cell[a];
    }
    return p;
  }

  // x along axis a in cell units from the lower face (the arithmetic of place()).
  // A sub-grid's is the whole grid's less its first cell: exact (a multiple of the coordinate's
  // last place, no larger than it), so both place x in the same cell.
  UNISPH_HOST_DEVICE T cell_coordinate(const Vec<T, D>& x, int a) const {
    return uncontracted::sub(uncontracted::mul(uncontracted::sub(x[a], box.lower[a]), axis_inverse_cell_size[a]),
                             T(first_cell[a]));
  }

  UNISPH_HOST_DEVICE Index linear_index(const Vec<int, D>& c) const {
    Index index = static_cast<Index>(c[D - 1]);
    for (int a = D - 2; a >= 0; --a) index = index * static_cast<Index>(cells[a]) + static_cast<Index>(c[a]);
    return index;
  }

  // |r|^2, summed along the axes in order, every product and sum rounded on its own.
  UNISPH_HOST_DEVICE T squared_distance(const Vec<T, D>& r) const {
    T s = uncontracted::mul(r[0], r[0]);
    for (int a = 1; a < D; ++a) s = uncontracted::add(s, uncontracted::mul(r[a], r[a]));
    return s;
  }

  // The neighbour test: strictly inside the cutoff (a pair at exactly the cutoff has W = 0).
  UNISPH_HOST_DEVICE bool within_cutoff(T squared_distance) const { return squared_distance < cutoff_squared; }

  // r_ij = x_i - x_j with its squared length; true when j is a neighbour of i.
  UNISPH_HOST_DEVICE bool test_pair(const Vec<T, D>& xi, const Vec<T, D>& xj, Vec<T, D>& r_ij, T& r2) const {
    for (int a = 0; a < D; ++a) r_ij[a] = uncontracted::sub(xi[a], xj[a]);
    r2 = squared_distance(r_ij);
    return within_cutoff(r2);
  }
};

}  // namespace unisph
