#pragma once
// Which cells of a layer get packages: a cell is core when the surface passes within one cell
// size of its centre, inner when it is not core but touches a core cell; the other cells are
// outside or inside, by the sign at their centre.
//
// The decision compares squared distances computed without fused multiply-adds (the closest
// point, the squared distance and the cell centre are all unfused, see closest_point.hpp and
// package_grid.hpp), so seq, par and the GPU tag the same cells and build the same layout.
//
// The coarsest layer decides every cell; a finer layer evaluates only the children of coarse
// core and inner cells (children of other cells lie farther than a cell size from the surface
// and inherit their parent's side).

#include <cstdint>

#include "unisph/core/config.hpp"
#include "unisph/grid/cell_tag.hpp"
#include "unisph/grid/package_grid.hpp"
#include "unisph/memory/view.hpp"
#include "unisph/neighbor/uncontracted_arithmetic.hpp"

namespace unisph {

template <int D, class Shape>
UNISPH_HOST_DEVICE inline CellTag decide_cell(const Shape& shape, const PackageGrid<D>& grid, const Vec<int, D>& cell) {
  const Vec<Real, D> centre = grid.cell_centre(cell);
  const auto nearest = shape.nearest(centre);
  const Real size = grid.cell_size();
  if (nearest.squared_distance < uncontracted::mul(size, size)) return CellTag::core;
  return shape.sign(centre, nearest) > 0 ? CellTag::outside : CellTag::inside;
}

template <int D, class Shape>
struct TagEveryCell {
  Shape shape;
  PackageGrid<D> grid;
  View<CellTag> tags;
  UNISPH_HOST_DEVICE void operator()(Index c) const { tags[c] = decide_cell<D>(shape, grid, grid.coordinates(c)); }
};

template <int D, class Shape>
struct TagUnderCoarseBand {
  Shape shape;
  PackageGrid<D> grid, coarse_grid;
  View<const CellTag> coarse_tags;
  View<CellTag> tags;
  UNISPH_HOST_DEVICE void operator()(Index c) const {
    const Vec<int, D> cell = grid.coordinates(c);
    Vec<int, D> parent;
    for (int k = 0; k < D; ++k) parent[k] = cell[k] / 2;
    const CellTag parent_tag = coarse_tags[coarse_grid.linear(parent)];
    tags[c] = has_package(parent_tag) ? decide_cell<D>(shape, grid, cell) : parent_tag;
  }
};

// Non-core cells next to a core cell become inner (reads one tag array, writes another).
template <int D>
struct TagInner {
  PackageGrid<D> grid;
  View<const CellTag> tags;
  View<CellTag> result;
  UNISPH_HOST_DEVICE void operator()(Index c) const {
    const CellTag tag = tags[c];
    result[c] = tag;
    if (tag == CellTag::core) return;
    const Vec<int, D> cell = grid.coordinates(c);
    for (int s = 0; s < neighbourhood_size<D>; ++s) {
      Vec<int, D> other = cell;
      int rest = s;
      for (int k = 0; k < D; ++k) {
        other[k] += rest % 3 - 1;
        rest /= 3;
      }
      if (grid.contains(other) && tags[grid.linear(other)] == CellTag::core) {
        result[c] = CellTag::inner;
        return;
      }
    }
  }
};

}  // namespace unisph
