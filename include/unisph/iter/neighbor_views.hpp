#pragma once
// Neighbour iteration written with hierarchical views (issue 8, part 3): the neighbours of
// particle i are found by a view of the cells around i's cell (iter::CellBlock) whose child view
// walks the particles of each cell (iter::CellParticles), and the cutoff test on each.
//
//   iter::for_each_neighbor(search, i, [&](Index j, const NeighborPair<T, D>& pair) { ... });
//
// `search` is the kernel-side NeighborSearch of a relation; this walk replaces its direct search
// (NeighborSearch::for_each_direct_neighbor) and gives the same pairs in the same order, bit for
// bit: the cells in the order of their linear index (axis 0 fastest; the direct search walks the
// same cells row by row, a row being consecutive places in the CSR), each cell's particles in CSR
// order, the same SearchGrid::test_pair. tests/iter/neighbor_views_test.cpp checks it on every
// policy.
//
// One difference in work, not in result: with cells smaller than the cutoff (grid.reach > 1) the
// direct search skips the cells of the (2 reach + 1)^D block whose nearest point is beyond the
// cutoff; this walk visits the whole block. Those cells hold no neighbour, so the pairs are the
// same; the candidates tested are more.

#include <type_traits>

#include "unisph/core/config.hpp"
#include "unisph/iter/cell_list_traits.hpp"
#include "unisph/iter/runtime.hpp"
#include "unisph/iter/view.hpp"
#include "unisph/neighbor/neighbor_pair.hpp"

namespace unisph::iter {

namespace detail {

// The pair's remaining geometry where NeighborPair keeps more than r_ij and |r_ij|^2.
template <class Pair>
UNISPH_HOST_DEVICE inline void complete_pair(Pair& pair) {
  if constexpr (requires { pair.complete(); }) pair.complete();
}

template <CellOrder Order, class T, int D, class F>
UNISPH_HOST_DEVICE inline void neighbors_in_block(const SearchGrid<T, D>& grid, const CellListArrays<T, D>& arrays,
                                                  const Vec<int, D>& cell, const Vec<T, D>& xi, Index i, bool inner,
                                                  F& f) {
  using Particles = View<CellParticles<T, D, Order>, direction::Forward, collectivity::None, CompileTimeTuple<>>;
  using Cells = View<CellBlock<T, D, Order>, direction::Forward, collectivity::None, CompileTimeTuple<>, Particles>;
  const Cells cells(CellBlock<T, D, Order>::around(arrays, grid.cells, cell, grid.reach));
  // One worker, offset 0 and jump 1 at both levels: every trip is an element, no slot is padding,
  // so the body does not test the slot (a test the compilers kept for every candidate).
  cells.for_each([&](SlotRef<const Vec<T, D>> slot) {
    NeighborPair<T, D> pair;
    if (grid.test_pair(xi, *slot, pair.r_ij, pair.squared_distance)) {
      // The index only for the few candidates within the cutoff (it costs a division by the
      // size of a position); i itself passes the test and is skipped here, as by the direct search.
      const Index j = particle_index(arrays.positions, slot);
      if (inner && j == i) return;
      complete_pair(pair);
      f(j, static_cast<const NeighborPair<T, D>&>(pair));
    }
  });
}

}  // namespace detail

// f(j, pair) for every neighbour j of source i (see the top of this file). Search is a
// NeighborSearch<T, D> (it needs its `sources`, `targets` and `inner`).
template <class Search, class F>
UNISPH_HOST_DEVICE inline void for_each_neighbor(const Search& search, Index i, F&& f) {
  const auto xi = search.sources[i];
  const auto& grid = search.targets.grid;
  const auto placement = grid.place(xi);
  // As the direct search: a NaN coordinate has no neighbours, nor (in an inner relation whose
  // list flags outside particles) a source outside the box.
  if (placement.status & placement_non_finite) return;
  if (search.inner && search.targets.flag_outside && placement.status != placement_inside) return;
  const CellListArrays arrays(search.targets);
  // The particle order is tested once here, not in the loop: two view types.
  if (search.targets.in_cell_order())
    detail::neighbors_in_block<CellOrder::contiguous>(grid, arrays, placement.cell, xi, i, search.inner, f);
  else
    detail::neighbors_in_block<CellOrder::indexed>(grid, arrays, placement.cell, xi, i, search.inner, f);
}

}  // namespace unisph::iter
