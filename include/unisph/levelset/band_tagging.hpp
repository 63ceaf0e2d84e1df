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
#include "unisph/levelset/shape_search.hpp"
#include "unisph/core/uncontracted_arithmetic.hpp"

namespace unisph {

// The decision from the nearest feature of the centre (what shape.nearest(centre) returns).
template <int D, class Shape, class Nearest>
UNISPH_HOST_DEVICE inline CellTag decide_cell_from(const Shape& shape, const PackageGrid<D>& grid,
                                                   const Vec<Real, D>& centre, const Nearest& nearest) {
  const Real size = grid.cell_size();
  if (nearest.squared_distance < uncontracted::mul(size, size)) return CellTag::core;
  return shape.sign(centre, nearest) > 0 ? CellTag::outside : CellTag::inside;
}

template <int D, class Shape>
UNISPH_HOST_DEVICE inline CellTag decide_cell(const Shape& shape, const PackageGrid<D>& grid, const Vec<int, D>& cell) {
  const Vec<Real, D> centre = grid.cell_centre(cell);
  return decide_cell_from<D>(shape, grid, centre, shape.nearest(centre));
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

// The same decisions as TagUnderCoarseBand, one coarse cell at a time, from what the coarse
// layer's distance stage computed for the children of its packages' cells
// (SignedDistanceInPackages, level_set_layer.hpp: the same decide_cell on the nearest triangle
// that shape.nearest would give, so the same tags, bit for bit). Host policies, triangle meshes.
struct TagChildrenFromCoarsePackages {
  PackageGrid<3> grid, coarse_grid;
  View<const CellTag> coarse_tags;
  View<const std::uint32_t> coarse_cell_package;
  View<const CellTag> children_tag;  // of the coarse layer, 8 per package
  View<CellTag> tags;
  UNISPH_HOST_DEVICE void operator()(Index c) const {
    const Vec<int, 3> parent = coarse_grid.coordinates(c);
    const CellTag parent_tag = coarse_tags[c];
    const bool decided = has_package(parent_tag);
    const Index first = decided ? Index(coarse_cell_package[c]) * 8 : 0;
    for (int j = 0; j < 8; ++j) {
      Vec<int, 3> child;
      for (int k = 0; k < 3; ++k) child[k] = 2 * parent[k] + ((j >> k) & 1);
      tags[grid.linear(child)] = decided ? children_tag[first + j] : parent_tag;
    }
  }
};

// Whether a cell of the 3^D block around `cell` is core.
template <int D>
UNISPH_HOST_DEVICE inline bool touches_core_cell(const PackageGrid<D>& grid, const View<const CellTag>& tags,
                                                 const Vec<int, D>& cell) {
  for (int s = 0; s < neighbourhood_size<D>; ++s) {
    const Vec<int, D> other = neighbour_in_block<D>(cell, s);
    if (grid.contains(other) && tags[grid.linear(other)] == CellTag::core) return true;
  }
  return false;
}

// Non-core cells next to a core cell become inner (reads one tag array, writes another). The
// coarsest layer looks at every cell; a finer one only under the coarse layer's packages
// (TagInnerUnderCoarsePackages, below): a core cell's parent is core (its centre lies within
// 1.87 fine = 0.93 coarse cell sizes of the surface), so a neighbour of a core cell has a parent
// that is core or next to a core cell, and so has a package.
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
    if (touches_core_cell<D>(grid, tags, cell)) result[c] = CellTag::inner;
  }
};

// The same on a finer layer, with work in proportion to the band rather than to the grid: each
// layer's tags are first copied whole (CopyCellTags), then only the 2^D children of the coarse
// layer's data packages are looked at (one thread per child, the only writer of its cell).
struct CopyCellTags {
  View<const CellTag> from;
  View<CellTag> to;
  UNISPH_HOST_DEVICE void operator()(Index c) const { to[c] = from[c]; }
};
template <int D>
struct TagInnerUnderCoarsePackages {
  PackageGrid<D> grid, coarse_grid;
  View<const std::uint64_t> coarse_package_cell;  // data packages from far_field_packages on
  View<const CellTag> tags;
  View<CellTag> result;  // holds a copy of tags
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    constexpr int children = 1 << D;
    const Vec<int, D> parent = coarse_grid.coordinates(coarse_package_cell[Index(far_field_packages) + i / children]);
    const int j = int(i % children);
    Vec<int, D> cell;
    for (int k = 0; k < D; ++k) cell[k] = 2 * parent[k] + ((j >> k) & 1);
    const Index c = grid.linear(cell);
    if (tags[c] == CellTag::core) return;
    if (touches_core_cell<D>(grid, tags, cell)) result[c] = CellTag::inner;
  }
};

}  // namespace unisph
