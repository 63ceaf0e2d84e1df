#pragma once
// A closed inside from a surface that may leak: on the coarsest layer every cell that is not
// core starts as inside except those on the border of the grid, and "outside" spreads through
// face neighbours that are not core until nothing changes. Holes in the surface smaller than
// the coarse cells are covered by core cells, so the outside cannot flow in through them and
// the sign of every cell away from the surface comes from connectivity, not from the normals
// of a broken surface. Each sweep reads one array and writes another (no cell is read while
// another thread writes it), so the sweeps are race-free and identical on every policy.

#include <cstdint>

#include "unisph/core/config.hpp"
#include "unisph/grid/cell_tag.hpp"
#include "unisph/grid/package_grid.hpp"
#include "unisph/memory/view.hpp"

namespace unisph {

template <int D>
struct SeedOutsideFromBorder {
  PackageGrid<D> grid;
  View<CellTag> tags;
  UNISPH_HOST_DEVICE void operator()(Index c) const {
    if (tags[c] == CellTag::core) return;
    const Vec<int, D> cell = grid.coordinates(c);
    bool border = false;
    for (int k = 0; k < D; ++k) border = border || cell[k] == 0 || cell[k] == grid.cells[k] - 1;
    tags[c] = border ? CellTag::outside : CellTag::inside;
  }
};

// One sweep from `tags` into `result`; returns 1 for a cell that turned outside.
template <int D>
struct SpreadOutside {
  PackageGrid<D> grid;
  View<const CellTag> tags;
  View<CellTag> result;
  UNISPH_HOST_DEVICE Index operator()(Index c) const {
    result[c] = tags[c];
    if (tags[c] != CellTag::inside) return 0;
    const Vec<int, D> cell = grid.coordinates(c);
    for (int k = 0; k < D; ++k)
      for (int side = -1; side <= 1; side += 2) {
        Vec<int, D> other = cell;
        other[k] += side;
        if (grid.contains(other) && tags[grid.linear(other)] == CellTag::outside) {
          result[c] = CellTag::outside;
          return 1;
        }
      }
    return 0;
  }
};

}  // namespace unisph
