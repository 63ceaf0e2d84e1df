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
  T stencil_radius;

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
    return g;
  }

  UNISPH_HOST_DEVICE Index cell_count() const {
    Index total = 1;
    for (int a = 0; a < D; ++a) total *= static_cast<Index>(cells[a]);
    return total;
  }

  // The cell of x, clamped into the grid, and whether x was outside the box or not finite
  // (a NaN coordinate is placed in cell 0 along its axis).
  UNISPH_HOST_DEVICE CellPlacement<D> place(const Vec<T, D>& x) const {
    CellPlacement<D> p{};
    for (int a = 0; a < D; ++a) {
      const T xa = x[a];
      if (!(xa == xa)) {
        p.status |= placement_non_finite;
        p.cell[a] = 0;
        continue;
      }
      if (xa < box.lower[a] || xa > box.upper[a]) p.status |= placement_out_of_box;
      const T t = uncontracted::mul(uncontracted::sub(xa, box.lower[a]), inverse_cell_size);
      // Compared as floating point before the conversion, which is undefined out of range.
      p.cell[a] = t < T(0) ? 0 : (t < T(cells[a]) ? static_cast<int>(t) : cells[a] - 1);
    }
    return p;
  }

  // x along axis a in cell units from the lower face (the arithmetic of place()).
  UNISPH_HOST_DEVICE T cell_coordinate(const Vec<T, D>& x, int a) const {
    return uncontracted::mul(uncontracted::sub(x[a], box.lower[a]), inverse_cell_size);
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
