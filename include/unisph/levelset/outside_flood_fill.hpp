#pragma once
// A closed inside from a surface that may leak, on the coarsest layer: the cells that are not
// core fall into connected regions (face neighbours that are not core), and every cell of a
// region takes the region's side:
//   - the region that touches the border of the grid is outside;
//   - any other region (the inside of a body, a hole of a 2D plate, a cavity enclosed in a 3D
//     body, the inside of an island within a hole) takes the side that most of its cells' own
//     signs (decided at their centres from the surface) say.
// Holes in the surface smaller than the coarse cells are covered by core cells, so the outside
// cannot flow in through them; and a region's side is a vote over all its cells, so the few
// cells whose sign a broken surface gets wrong do not decide it. (Taking every enclosed region
// as inside, as a flood fill from the border alone does, gets the holes of 2D polygons and the
// cavities of 3D bodies wrong.)
//
// The regions are labelled by the smallest cell index they hold: sweeps between two arrays
// (each cell takes the smallest label among itself, its face neighbours that are not core and
// the label of its label) until one changes nothing, so the sweeps are race-free and give the
// same labels on every policy. The vote adds +1 (outside) or -1 (inside) per cell into its
// label's counter with integer atomics: the same totals on every policy.

#include <cstdint>

#include "unisph/core/config.hpp"
#include "unisph/exec/atomic.hpp"
#include "unisph/grid/cell_tag.hpp"
#include "unisph/grid/package_grid.hpp"
#include "unisph/memory/view.hpp"

namespace unisph {

inline constexpr std::uint32_t no_region = 0xffffffffu;

// Each cell that is not core starts as its own region; the cells on the border of the grid
// start as region 0 (cell 0 is on the border, so 0 is the smallest label there anyway).
template <int D>
struct StartRegions {
  PackageGrid<D> grid;
  View<const CellTag> tags;
  View<std::uint32_t> label;
  View<int> votes;
  UNISPH_HOST_DEVICE void operator()(Index c) const {
    votes[c] = 0;
    if (tags[c] == CellTag::core) {
      label[c] = no_region;
      return;
    }
    const Vec<int, D> cell = grid.coordinates(c);
    bool border = false;
    for (int k = 0; k < D; ++k) border = border || cell[k] == 0 || cell[k] == grid.cells[k] - 1;
    label[c] = border ? 0u : std::uint32_t(c);
  }
};

// One sweep from `label` into `result`; returns 1 for a cell whose label fell.
template <int D>
struct MergeRegions {
  PackageGrid<D> grid;
  View<const std::uint32_t> label;
  View<std::uint32_t> result;
  UNISPH_HOST_DEVICE Index operator()(Index c) const {
    const std::uint32_t own = label[c];
    result[c] = own;
    if (own == no_region) return 0;
    // The label of the label: a cell of the same region, whose label is that region's too.
    std::uint32_t smallest = label[own] < own ? label[own] : own;
    const Vec<int, D> cell = grid.coordinates(c);
    for (int k = 0; k < D; ++k)
      for (int side = -1; side <= 1; side += 2) {
        Vec<int, D> other = cell;
        other[k] += side;
        if (!grid.contains(other)) continue;
        const std::uint32_t l = label[grid.linear(other)];
        if (l < smallest) smallest = l;  // no_region is the largest value, so core cells never win
      }
    result[c] = smallest;
    return smallest != own ? 1 : 0;
  }
};

// Every cell that is not core adds its own side to its region's counter.
template <int D>
struct VoteRegionSide {
  View<const CellTag> tags;
  View<const std::uint32_t> label;
  View<int> votes;
  UNISPH_HOST_DEVICE void operator()(Index c) const {
    const std::uint32_t l = label[c];
    if (l == no_region) return;
    atomic_add(&votes[l], tags[c] == CellTag::outside ? 1 : -1);
  }
};

// Every cell that is not core takes its region's side (ties: inside).
template <int D>
struct SideOfRegion {
  View<const std::uint32_t> label;
  View<const int> votes;
  View<CellTag> tags;
  UNISPH_HOST_DEVICE void operator()(Index c) const {
    const std::uint32_t l = label[c];
    if (l == no_region) return;
    tags[c] = l == 0u || votes[l] > 0 ? CellTag::outside : CellTag::inside;
  }
};

}  // namespace unisph
