#pragma once
// NeighborSearch<T, D>: the kernel-side face of a neighbour relation. A kernel holds one by
// value and calls
//
//   search.for_each_neighbor(i, [&](Index j, const NeighborPair<T, D>& pair) { ... });
//
// inside its UNISPH_HOST_DEVICE function (a lambda defined and called in device code is
// fine for nvcc: only lambdas passed from host to a launch need extended-lambda support).
//
// Two ways of finding the neighbours, chosen by the relation (see docs/neighbor_search.md):
//   direct search  walks the particles of the 3^D cells around x_i and applies the cutoff
//                  test on the fly (nothing stored per pair; the device default);
//   stored lists   walks a CSR list of j built by a direct search at the last update (the
//                  host default).
// Both give the same j with the same r_ij (recomputed from the current positions).
//
// Particles i are "sources" (for an inner relation the body's own particles, for a contact
// relation another body's); the j come from the target cell list. In an inner relation j == i
// is skipped, and a source in the flagged bucket (OutsideParticles::flag) has no neighbours.

#include <cstdint>

#include "unisph/neighbor/cell_linked_list.hpp"
#include "unisph/neighbor/neighbor_pair.hpp"

namespace unisph {

template <class T, int D>
struct NeighborSearch {
  View<const Vec<T, D>> sources;  // x_i
  CellListView<T, D> targets;     // the x_j and their cells
  bool inner;                     // sources are the targets: skip j == i
  // Stored lists (used when list_offsets is not empty): the j of i are
  // list_neighbors[list_offsets[i] .. list_offsets[i + 1]).
  View<const std::uint64_t> list_offsets;
  View<const std::uint32_t> list_neighbors;

  UNISPH_HOST_DEVICE bool uses_stored_lists() const { return !list_offsets.empty(); }

  template <class F>
  UNISPH_HOST_DEVICE void for_each_neighbor(Index i, F&& f) const {
    if (uses_stored_lists())
      for_each_stored_neighbor(i, f);
    else
      for_each_direct_neighbor(i, f);
  }

  template <class F>
  UNISPH_HOST_DEVICE void for_each_stored_neighbor(Index i, F&& f) const {
    const Vec<T, D> xi = sources[i];
    const std::uint64_t end = list_offsets[i + 1];
    for (std::uint64_t k = list_offsets[i]; k < end; ++k) {
      const Index j = list_neighbors[k];
      NeighborPair<T, D> pair;
      targets.grid.test_pair(xi, targets.positions[j], pair.r_ij, pair.squared_distance);
      f(j, static_cast<const NeighborPair<T, D>&>(pair));
    }
  }

  template <class F>
  UNISPH_HOST_DEVICE void for_each_direct_neighbor(Index i, F&& f) const {
    const SearchGrid<T, D>& grid = targets.grid;
    const Vec<T, D> xi = sources[i];
    const CellPlacement<D> placement = grid.place(xi);
    if (placement.status & placement_non_finite) return;
    if (inner && targets.flag_outside && placement.status != placement_inside) return;
    const Vec<int, D>& c = placement.cell;
    const bool cell_order = targets.in_cell_order();
    // The cells along axis 0 are consecutive: one range of particles per row of three cells.
    const int x_first = c[0] > 0 ? c[0] - 1 : 0;
    const int x_last = c[0] + 1 < grid.cells[0] ? c[0] + 1 : grid.cells[0] - 1;
    constexpr int rows = D == 2 ? 3 : 9;
    for (int row = 0; row < rows; ++row) {
      Vec<int, D> first = c;
      first[0] = x_first;
      first[1] = c[1] + row % 3 - 1;
      if (first[1] < 0 || first[1] >= grid.cells[1]) continue;
      if constexpr (D == 3) {
        first[2] = c[2] + row / 3 - 1;
        if (first[2] < 0 || first[2] >= grid.cells[2]) continue;
      }
      const Index first_cell = grid.linear_index(first);
      const Index last_cell = first_cell + static_cast<Index>(x_last - x_first);
      const std::uint32_t begin = targets.offsets[first_cell];
      const std::uint32_t end = targets.offsets[last_cell + 1];
      if (cell_order) {
        // The row's particles are the indices [begin, end): contiguous reads, no indirection.
        for (std::uint32_t j = begin; j < end; ++j) visit(i, xi, j, f);
      } else {
        for (std::uint32_t k = begin; k < end; ++k) visit(i, xi, targets.particles[k], f);
      }
    }
  }

  template <class F>
  UNISPH_HOST_DEVICE void visit(Index i, const Vec<T, D>& xi, Index j, F& f) const {
    if (inner && j == i) return;
    NeighborPair<T, D> pair;
    if (targets.grid.test_pair(xi, targets.positions[j], pair.r_ij, pair.squared_distance))
      f(j, static_cast<const NeighborPair<T, D>&>(pair));
  }

  // How many particles a direct search of i looks at (candidate pairs, for benchmarks).
  UNISPH_HOST_DEVICE Index candidate_count(Index i) const {
    const SearchGrid<T, D>& grid = targets.grid;
    const CellPlacement<D> placement = grid.place(sources[i]);
    if (placement.status & placement_non_finite) return 0;
    if (inner && targets.flag_outside && placement.status != placement_inside) return 0;
    const Vec<int, D>& c = placement.cell;
    const int x_first = c[0] > 0 ? c[0] - 1 : 0;
    const int x_last = c[0] + 1 < grid.cells[0] ? c[0] + 1 : grid.cells[0] - 1;
    Index count = 0;
    constexpr int rows = D == 2 ? 3 : 9;
    for (int row = 0; row < rows; ++row) {
      Vec<int, D> first = c;
      first[0] = x_first;
      first[1] = c[1] + row % 3 - 1;
      if (first[1] < 0 || first[1] >= grid.cells[1]) continue;
      if constexpr (D == 3) {
        first[2] = c[2] + row / 3 - 1;
        if (first[2] < 0 || first[2] >= grid.cells[2]) continue;
      }
      const Index first_cell = grid.linear_index(first);
      count += targets.offsets[first_cell + static_cast<Index>(x_last - x_first) + 1] - targets.offsets[first_cell];
    }
    return count;
  }
};

}  // namespace unisph
