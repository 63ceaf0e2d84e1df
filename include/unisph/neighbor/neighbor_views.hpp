#pragma once
// Neighbour iteration written with hierarchical views (issue 8, part 3):
//
//   iter::for_each_neighbor(search, i, [&](Index j, const NeighborPair<T, D>& pair) { ... });
//
// `search` is the kernel-side NeighborSearch of a relation. The walk: the stencil around x_i as
// planes -> rows of cells (iter/stencil_traits.hpp), trimmed to the cutoff, each row's CSR places
// one contiguous range walked with the cutoff test on each candidate (tests/iter/neighbor_views_test.cpp
// checks it against a hand-written row walk on every policy, bit for bit).
//
// It is the engine's search: NeighborSearch walks its stencil with these views, so there is one
// neighbour-iteration implementation (docs/views.md).

#include "unisph/core/config.hpp"
#include "unisph/neighbor/stencil_traits.hpp"
#include "unisph/neighbor/neighbor_search.hpp"

namespace unisph::iter {

// f(j, pair) for every neighbour j of source i: the engine's direct search, which is this walk
// (NeighborSearch::for_each_direct_neighbor: for_each_stencil_row, each row's places a counted loop
// with the cutoff test on each candidate).
template <class T, int D, class F>
UNISPH_HOST_DEVICE inline void for_each_neighbor(const NeighborSearch<T, D>& search, Index i, F&& f) {
  search.for_each_direct_neighbor(i, f);
}

}  // namespace unisph::iter
