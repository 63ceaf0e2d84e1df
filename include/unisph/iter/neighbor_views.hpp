#pragma once
// Neighbour iteration written with hierarchical views (issue 8, part 3):
//
//   iter::for_each_neighbor(search, i, [&](Index j, const NeighborPair<T, D>& pair) { ... });
//
// `search` is the kernel-side NeighborSearch of a relation. The walk: the stencil around x_i as
// planes -> rows of cells -> the CSR places of each row (iter/stencil_traits.hpp), trimmed to the
// cutoff as the direct search trims it, each row walked by View::for_each with the cutoff test on
// each candidate. It gives the pairs of NeighborSearch::for_each_direct_neighbor in the same order,
// bit for bit (tests/iter/neighbor_views_test.cpp, every policy).
//
// It is not the engine's search: as the engine it kept the SPH solver within 5 % on an H100 but made
// neighbor_bench's GPU density pass 9 % (Morton order) to 27 % (through the cell-ordered copy of the
// positions) slower, with more registers per thread (docs/views.md, "Not done yet").

#include "unisph/core/config.hpp"
#include "unisph/iter/stencil_traits.hpp"
#include "unisph/neighbor/neighbor_search.hpp"

namespace unisph::iter {

namespace detail {

// f(j, pair) for the neighbours of x_i among the candidates of one row.
template <class T, int D, class Reader, class F>
UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE inline void neighbors_in_row(const SearchGrid<T, D>& grid, const row_view_t<T, D>& row,
                                                const Vec<T, D>& xi, const Reader& read, F& f) {
  row.for_each([&](typename Reader::Slot slot) {
    if (read.is_self(slot)) return;
    NeighborPair<T, D> pair;
    if (grid.test_pair(xi, read.position(slot), pair.r_ij, pair.squared_distance)) {
      pair.complete();
      f(read.index(slot), static_cast<const NeighborPair<T, D>&>(pair));
    }
  });
}

}  // namespace detail

// f(j, pair) for every neighbour j of source i (see the top of this file). Host compilers inline
// the whole walk and f into it (UNISPH_NEIGHBOR_LOOP), as for the direct search.
template <class T, int D, class F>
UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE inline void for_each_neighbor(const NeighborSearch<T, D>& search, Index i, F&& f) {
  const Vec<T, D> xi = search.sources[i];
  const SearchGrid<T, D>& grid = search.targets.grid;
  const CellPlacement<D> placement = grid.place(xi);
  // As the direct search: a NaN coordinate has no neighbours, nor (in an inner relation whose
  // list flags outside particles) a source outside the box.
  if (placement.status & placement_non_finite) return;
  if (search.inner && search.targets.flag_outside && placement.status != placement_inside) return;
  // The list by pointer: its arrays and the grid stay kernel parameters (copies held registers).
  const StencilArrays<T, D> arrays{&search.targets};
  const bool contiguous = search.targets.in_cell_order();
  const auto by_index = CandidateReader<T, D, CellOrder::indexed>::of(arrays, search.inner, i);
  const auto by_place = CandidateReader<T, D, CellOrder::contiguous>::of(arrays, search.inner, i);
  // The order is chosen per row (one branch per row), so the stencil is walked by one piece of code.
  for_each_row<T, D>(stencil_around(grid, arrays, placement, xi), [&](const row_view_t<T, D>& row) {
    if (contiguous)
      detail::neighbors_in_row(grid, row, xi, by_place, f);
    else
      detail::neighbors_in_row(grid, row, xi, by_index, f);
  });
}

}  // namespace unisph::iter
