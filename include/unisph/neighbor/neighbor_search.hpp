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
//   direct search  walks the particles of the cells around x_i (the 3^D around its own;
//                  with cells smaller than the cutoff, those of the (2 reach + 1)^D that
//                  come within the cutoff) and applies the cutoff test on the fly (nothing
//                  stored per pair; the device default);
//   stored lists   walks CSR lists of j and of each pair's geometry (NeighborPair), both built
//                  by a direct search at the last update (the host default): a pass loads no
//                  neighbour position and computes no distance.
// Both give the same j. Their geometry differs once the particles moved after the update:
// a direct search measures r_ij from the current positions, stored lists keep r_ij, |r_ij|^2
// and |r_ij| of the configuration at the update (what dual time stepping wants: the
// configuration is that of the advection step, reused by its acoustic steps).
//
// Particles i are "sources" (for an inner relation the body's own particles, for a contact
// relation another body's); the j come from the target cell list. In an inner relation j == i
// is skipped, and a source in the flagged bucket (OutsideParticles::flag) has no neighbours.

#include <cmath>
#include <cstdint>

#include "unisph/neighbor/stencil_traits.hpp"
#include "unisph/neighbor/cell_linked_list.hpp"
#include "unisph/neighbor/neighbor_pair.hpp"

// Host compilers: inline everything a neighbour loop calls, the kernel's lambda included, so
// the pair's values stay in registers (GCC does not inline a lambda called from both the
// stored and the direct loop on its own; measured: the dam break's pressure pass then runs
// as a separate function). nvcc's device pass inlines these anyway.
#if defined(__GNUC__) && !UNISPH_DEVICE_CODE
#define UNISPH_NEIGHBOR_LOOP __attribute__((flatten))
#else
#define UNISPH_NEIGHBOR_LOOP
#endif

namespace unisph {

// A source of an inner relation taken in the cell list's order: its place in that order
// (`slot`, the position in CellListView::particles) and its particle index.
struct CellOrderSource {
  Index slot;
  Index particle;
};

template <class T, int D>
struct NeighborSearch {
  View<const Vec<T, D>> sources;  // x_i
  CellListView<T, D> targets;     // the x_j and their cells
  bool inner;                     // sources are the targets: skip j == i
  // Stored lists (used when list_counts is not empty, see stored_neighbor_lists.hpp): the j of
  // i and their geometry are in slots k < list_counts[i], at i * list_source_stride +
  // k * list_slot_stride of list_neighbors and list_pairs.
  View<const std::uint32_t> list_counts;
  View<const std::uint32_t> list_neighbors;
  View<const NeighborPair<T, D>> list_pairs;
  std::uint64_t list_source_stride = 0, list_slot_stride = 0;
  // Optional, with stored lists: a value per pair cached at the update, in the slots' layout
  // (see for_each_weighted_neighbor).
  View<const T> list_weights;

  UNISPH_HOST_DEVICE bool uses_stored_lists() const { return !list_counts.empty(); }

  // The k-th particle of the cell list's order (the particles of cell 0, then of cell 1, ...),
  // for an inner relation, whose sources are the cell list's particles. A kernel that takes its
  // i this way, i = source_in_cell_order(k) for k in [0, n), visits every particle once, and
  // the lanes of a warp then hold particles of the same cells, which walk the same rows, even
  // where the particles are not stored in cell order (e.g. in Morton order). k runs over every
  // particle of the cell list, ghosts included: a set with ghosts skips i >= its owned count.
  UNISPH_HOST_DEVICE Index source_in_cell_order(Index k) const {
    return targets.in_cell_order() ? k : Index(targets.particles[k]);
  }

  // The same as a CellOrderSource, for the overload of for_each_neighbor below.
  UNISPH_HOST_DEVICE CellOrderSource cell_order_source(Index k) const { return {k, source_in_cell_order(k)}; }

  // f(j, pair) for every neighbour of s.particle. Where the cell list keeps its positions in
  // cell order (CellLinkedList::store_positions_in_cell_order) and the particles are not in cell
  // order themselves, the direct search reads x_i and the candidates from that copy: a row of
  // cells is one contiguous range, one aligned load per candidate, and j is loaded only for the
  // pairs within the cutoff. The pairs and their geometry are then those of the positions at the
  // build (the same as for_each_neighbor(s.particle, f) while the particles have not moved since).
  template <class F>
  UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void for_each_neighbor(CellOrderSource s, F&& f) const {
    if (uses_stored_lists() || !inner || targets.points.empty() || targets.in_cell_order()) {
      for_each_neighbor(s.particle, f);
      return;
    }
    const Vec<T, D> xi = targets.points[s.slot].position();
    for_each_candidate_range(xi, [&](std::uint32_t begin, std::uint32_t end) {
      for (std::uint32_t k = begin; k < end; ++k) {
        if (k == s.slot) continue;  // i itself: its one place in the list
        NeighborPair<T, D> pair;
        if (targets.grid.test_pair(xi, targets.points[k].position(), pair.r_ij, pair.squared_distance)) {
          pair.complete();
          f(Index(targets.particles[k]), static_cast<const NeighborPair<T, D>&>(pair));
        }
      }
    });
  }

  // f(j, pair, w) for every neighbour, with w = weight(pair). Stored lists that carry a weight
  // column (filled with this same `weight` at the relation's update(policy, weight); the
  // relation's search(context, weight) hands the column only then) give the cached value;
  // otherwise weight(pair) is computed here, pair by pair. The values are the same bits: the
  // cached ones were computed by the same function from the same stored pair. SPH passes
  // dW/dr, whose distance is frozen over an advection step: computed once per build instead
  // of at every acoustic pass.
  // Runs = false (here and below) leaves the walk of an id-ordered list by runs out of the code,
  // for a kernel's common case where the caller knows targets.run_end is empty: the same
  // neighbours in the same order, fewer registers.
  template <bool Runs = true, class W, class F>
  UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void for_each_weighted_neighbor(Index i, const W& weight, F&& f) const {
    if (uses_stored_lists() && !list_weights.empty()) {
      const std::uint64_t n = list_counts[i];
      std::uint64_t slot = i * list_source_stride;
      for (std::uint64_t k = 0; k < n; ++k, slot += list_slot_stride)
        f(Index(list_neighbors[slot]), list_pairs[slot], list_weights[slot]);
    } else {
      for_each_neighbor<Runs>(i, [&](Index j, const NeighborPair<T, D>& pair) { f(j, pair, weight(pair)); });
    }
  }

  template <bool Runs = true, class F>
  UNISPH_HOST_DEVICE void for_each_neighbor(Index i, F&& f) const {
    if (uses_stored_lists())
      for_each_stored_neighbor(i, f);
    else
      for_each_direct_neighbor<Runs>(i, f);
  }

  // The cached geometry of the last update; no position is read.
  template <class F>
  UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void for_each_stored_neighbor(Index i, F&& f) const {
    const std::uint64_t n = list_counts[i];
    std::uint64_t slot = i * list_source_stride;
    for (std::uint64_t k = 0; k < n; ++k, slot += list_slot_stride) f(Index(list_neighbors[slot]), list_pairs[slot]);
  }

  // The direct search: the candidates of the stencil's rows (for_each_direct_candidate) with the
  // cutoff test on each.
  template <bool Runs = true, class F>
  UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void for_each_direct_neighbor(Index i, F&& f) const {
    for_each_direct_candidate<Runs>(i, [&](Index j, const Vec<T, D>& xi, const Vec<T, D>& xj) {
      NeighborPair<T, D> pair;
      if (targets.grid.test_pair(xi, xj, pair.r_ij, pair.squared_distance)) {
        pair.complete();
        f(j, static_cast<const NeighborPair<T, D>&>(pair));
      }
    });
  }

  // g(j, x_i, x_j) for every candidate j of i (the particles of the walked cells, j != i in
  // an inner relation), in the order of the direct search; the cutoff test is g's.
  template <bool Runs = true, class G>
  UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void for_each_direct_candidate(Index i, G&& g) const {
    const Vec<T, D> xi = sources[i];
    const bool cell_order = targets.in_cell_order();
    for_each_candidate_range(xi, [&](std::uint32_t begin, std::uint32_t end) {
      if (begin >= end) return;
      if (cell_order) {
        // The row's particles are the indices [begin, end): contiguous reads, no indirection.
        for (std::uint32_t j = begin; j < end; ++j)
          if (!(inner && j == i)) g(Index(j), xi, targets.positions[j]);
      } else if (Runs && !targets.run_end.empty()) {
        // Ordered by id: each run of consecutive indices is read as such, in the list's order
        // (the same order as the index list's, so the same sums).
        for (std::uint32_t k = begin; k < end;) {
          const std::uint32_t stop = targets.run_end[k] < end ? targets.run_end[k] : end;
          const std::uint32_t first = targets.particles[k];
          const std::uint32_t last = first + (stop - k);
          for (std::uint32_t j = first; j < last; ++j)
            if (!(inner && j == i)) g(Index(j), xi, targets.positions[j]);
          k = stop;
        }
      } else {
        for (std::uint32_t k = begin; k < end; ++k) {
          const Index j = targets.particles[k];
          if (!(inner && j == i)) g(j, xi, targets.positions[j]);
        }
      }
    });
  }

  // How many particles a direct search of i looks at (candidate pairs, for benchmarks).
  UNISPH_HOST_DEVICE Index candidate_count(Index i) const {
    Index count = 0;
    for_each_candidate_range(sources[i], [&](std::uint32_t begin, std::uint32_t end) { count += end - begin; });
    return count;
  }

  // Calls g(begin, end) for the CSR ranges [begin, end) of `targets.particles` that can hold
  // neighbours of x: one per row of cells of the stencil's view (for_each_stencil_row). The
  // places of a row are one contiguous range, which every neighbour loop walks as a counted loop
  // (as a view of its own, the row's places measured 7 to 18 % slower in neighbor_bench's GPU
  // density pass on an H100; docs/views.md).
  template <class G>
  UNISPH_HOST_DEVICE void for_each_candidate_range(const Vec<T, D>& x, G&& g) const {
    for_each_stencil_row(x, [&](const iter::row_view_t<T, D>& row) { g(row.container().begin, row.container().end); });
  }

  // The one walk of the direct search: g(row) for the view of each row of cells of the stencil
  // around x (iter/stencil_traits.hpp: planes -> rows of cells -> the CSR places of a row;
  // consecutive cells along axis 0 are consecutive places, so a row is one contiguous range).
  // The stencil is the 3^D cells around x's cell; with cells smaller than the cutoff
  // (grid.reach > 1), those of the (2 reach + 1)^D that come within the cutoff, trimmed axis by
  // axis (planes, then rows, then the ends of each row) in cell units with a padded radius
  // (SearchGrid::stencil_radius), so it never skips a neighbour. A NaN coordinate has no
  // neighbours, nor, in an inner relation whose list flags outside particles, a source outside
  // the box; other positions outside the box walk the whole clamped stencil.
  template <class G>
  UNISPH_HOST_DEVICE void for_each_stencil_row(const Vec<T, D>& x, G&& g) const {
    const CellPlacement<D> placement = targets.grid.place(x);
    if (placement.status & placement_non_finite) return;
    if (inner && targets.flag_outside && placement.status != placement_inside) return;
    // The list by pointer: its arrays and the grid stay kernel parameters (copies held registers).
    iter::for_each_row<T, D>(iter::stencil_around(targets.grid, iter::StencilArrays<T, D>{&targets}, placement, x), g);
  }
};

}  // namespace unisph
