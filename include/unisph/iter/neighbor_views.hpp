#pragma once
// Neighbour iteration written with hierarchical views (issue 8, part 3):
//
//   iter::for_each_neighbor(search, i, [&](Index j, const NeighborPair<T, D>& pair) { ... });
//
// `search` is the kernel-side NeighborSearch of a relation. Its direct search is itself the view
// walk: the stencil around x_i as planes -> rows of cells -> the CSR places of each row
// (iter/stencil_traits.hpp), with the cutoff test on each candidate; there is no other
// implementation of the neighbour walk. This function is that search under the views' name, for
// code written against iter/ (tests/iter/neighbor_views_test.cpp compares it, pair by pair and
// bit for bit, with the row walk the engine used before, written out in the test).
//
// A cell-by-cell view walk (a CellBlock of the (2 reach + 1)^D cells, each cell's particles a
// child view) gives the same pairs in the same order; it is not used for the search, because it
// runs 27 (or 125) short loops instead of 9 (or the trimmed 25) row loops and does not trim: inside
// the GPU SPH kernels it measured 25-30 % slower (docs/views.md).

#include "unisph/core/config.hpp"
#include "unisph/neighbor/neighbor_search.hpp"

namespace unisph::iter {

// f(j, pair) for every neighbour j of source i: NeighborSearch::for_each_direct_neighbor.
template <class T, int D, class F>
UNISPH_HOST_DEVICE inline void for_each_neighbor(const NeighborSearch<T, D>& search, Index i, F&& f) {
  search.for_each_direct_neighbor(i, f);
}

}  // namespace unisph::iter
