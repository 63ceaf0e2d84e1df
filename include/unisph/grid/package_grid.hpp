#pragma once
// The background mesh of a sparse grid: a box of cells, each of which may own a data package of
// 4^D data points. Data points sit at the centres of the sub-cells of spacing
// data_spacing = cell_size / 4, so a cell's package covers exactly that cell and neighbouring
// packages continue the same regular lattice.
//
// Positions are computed as origin + (integer + 1/2) * data_spacing in one rounding per product
// and sum, never fused into a multiply-add (closest_point.hpp explains why), so that the host and
// the device place every point and every cell centre on the same bits.

#include <cstdint>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/core/uncontracted_arithmetic.hpp"

namespace unisph {

// Data points along each axis of a package.
inline constexpr int package_size = 4;

template <int D>
inline constexpr int package_points = D == 2 ? package_size * package_size : package_size * package_size * package_size;

// Packages in the 3^D block around (and including) a package.
template <int D>
inline constexpr int neighbourhood_size = D == 2 ? 9 : 27;

// Member s (0 .. 3^D - 1) of the 3^D block around `centre` (cells, packages or data points):
// offset (s % 3 - 1, s / 3 % 3 - 1, ...), so s = (3^D - 1) / 2 is the centre itself.
template <int D>
UNISPH_HOST_DEVICE inline Vec<int, D> neighbour_in_block(const Vec<int, D>& centre, int s) {
  Vec<int, D> other = centre;
  for (int k = 0; k < D; ++k) {
    other[k] += s % 3 - 1;
    s /= 3;
  }
  return other;
}

template <int D>
struct PackageGrid {
  static_assert(D == 2 || D == 3, "a package grid is 2D or 3D.");
  Vec<Real, D> origin;   // lower corner of cell (0, ..., 0)
  Real data_spacing;     // spacing of the data points; the cell size is 4 times as large
  Vec<int, D> cells;     // cells along each axis

  UNISPH_HOST_DEVICE Real cell_size() const { return data_spacing * Real(package_size); }
  UNISPH_HOST_DEVICE Index cell_count() const {
    Index n = 1;
    for (int k = 0; k < D; ++k) n *= Index(cells[k]);
    return n;
  }
  // Axis 0 varies fastest.
  UNISPH_HOST_DEVICE Index linear(const Vec<int, D>& cell) const {
    Index index = Index(cell[D - 1]);
    for (int k = D - 2; k >= 0; --k) index = index * Index(cells[k]) + Index(cell[k]);
    return index;
  }
  UNISPH_HOST_DEVICE Vec<int, D> coordinates(Index linear_index) const {
    Vec<int, D> cell;
    for (int k = 0; k < D; ++k) {
      cell[k] = int(linear_index % Index(cells[k]));
      linear_index /= Index(cells[k]);
    }
    return cell;
  }
  UNISPH_HOST_DEVICE bool contains(const Vec<int, D>& cell) const {
    for (int k = 0; k < D; ++k)
      if (cell[k] < 0 || cell[k] >= cells[k]) return false;
    return true;
  }
  // The position of global data point `point` (4 * cell + local index within the package).
  UNISPH_HOST_DEVICE Vec<Real, D> data_position(const Vec<int, D>& point) const {
    Vec<Real, D> x;
    for (int k = 0; k < D; ++k)
      x[k] = uncontracted::add(origin[k], uncontracted::mul(Real(point[k]) + Real(0.5), data_spacing));
    return x;
  }
  UNISPH_HOST_DEVICE Vec<Real, D> data_position(const Vec<int, D>& cell, int local_point) const {
    Vec<int, D> point;
    for (int k = 0; k < D; ++k) {
      point[k] = package_size * cell[k] + local_point % package_size;
      local_point /= package_size;
    }
    return data_position(point);
  }
  // Cell centres lie halfway between data points 1 and 2 of the cell: origin + (4c + 2) * spacing.
  UNISPH_HOST_DEVICE Vec<Real, D> cell_centre(const Vec<int, D>& cell) const {
    Vec<Real, D> x;
    for (int k = 0; k < D; ++k)
      x[k] = uncontracted::add(origin[k], uncontracted::mul(Real(package_size * cell[k] + 2), data_spacing));
    return x;
  }
  // The cell holding a position (possibly outside the grid).
  UNISPH_HOST_DEVICE Vec<int, D> cell_of(const Vec<Real, D>& x) const {
    Vec<int, D> cell;
    const Real size = cell_size();
    for (int k = 0; k < D; ++k) cell[k] = int(floor_real((x[k] - origin[k]) / size));
    return cell;
  }

 private:
  UNISPH_HOST_DEVICE static Real floor_real(Real v) {
    const long long t = (long long)v;
    return Real(t) > v ? Real(t - 1) : Real(t);
  }
};

// Local index of a data point inside its package (axis 0 fastest).
template <int D>
UNISPH_HOST_DEVICE inline int local_point_index(const Vec<int, D>& local) {
  int index = local[D - 1];
  for (int k = D - 2; k >= 0; --k) index = index * package_size + local[k];
  return index;
}

}  // namespace unisph
