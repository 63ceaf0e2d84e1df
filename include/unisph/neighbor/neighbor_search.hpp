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
  template <class W, class F>
  UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void for_each_weighted_neighbor(Index i, const W& weight, F&& f) const {
    if (uses_stored_lists() && !list_weights.empty()) {
      const std::uint64_t n = list_counts[i];
      std::uint64_t slot = i * list_source_stride;
      for (std::uint64_t k = 0; k < n; ++k, slot += list_slot_stride)
        f(Index(list_neighbors[slot]), list_pairs[slot], list_weights[slot]);
    } else {
      for_each_neighbor(i, [&](Index j, const NeighborPair<T, D>& pair) { f(j, pair, weight(pair)); });
    }
  }

  template <class F>
  UNISPH_HOST_DEVICE void for_each_neighbor(Index i, F&& f) const {
    if (uses_stored_lists())
      for_each_stored_neighbor(i, f);
    else
      for_each_direct_neighbor(i, f);
  }

  // The cached geometry of the last update; no position is read.
  template <class F>
  UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void for_each_stored_neighbor(Index i, F&& f) const {
    const std::uint64_t n = list_counts[i];
    std::uint64_t slot = i * list_source_stride;
    for (std::uint64_t k = 0; k < n; ++k, slot += list_slot_stride) f(Index(list_neighbors[slot]), list_pairs[slot]);
  }

  // The row walk below, not the hierarchical view walk (iter::for_each_neighbor, iter/neighbor_views.hpp:
  // the stencil as planes -> rows of cells -> the CSR places of a row, the same pairs in the same
  // order). With the view walk as the engine (commit 27d81cb of branch wt-views) the SPH solver on an
  // H100 stayed within 5 % (bench/sph, 3D dx 0.0125 float -3.7 %, double +0.1 % fluid steps/s), but
  // neighbor_bench's GPU density pass did not: +9 % in Morton order, +17 to +27 % through the
  // cell-ordered copy of the positions (its kernel: 40 registers against this walk's 32; docs/views.md).
  template <class F>
  UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void for_each_direct_neighbor(Index i, F&& f) const {
    for_each_direct_candidate(i, [&](Index j, const Vec<T, D>& xi, const Vec<T, D>& xj) {
      NeighborPair<T, D> pair;
      if (targets.grid.test_pair(xi, xj, pair.r_ij, pair.squared_distance)) {
        pair.complete();
        f(j, static_cast<const NeighborPair<T, D>&>(pair));
      }
    });
  }

  // g(j, x_i, x_j) for every candidate j of i (the particles of the walked cells, j != i in
  // an inner relation), in the order of the direct search; the cutoff test is g's.
  template <class G>
  UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void for_each_direct_candidate(Index i, G&& g) const {
    const Vec<T, D> xi = sources[i];
    const bool cell_order = targets.in_cell_order();
    for_each_candidate_range(xi, [&](std::uint32_t begin, std::uint32_t end) {
      if (begin >= end) return;
      if (cell_order) {
        // The row's particles are the indices [begin, end): contiguous reads, no indirection.
        for (std::uint32_t j = begin; j < end; ++j)
          if (!(inner && j == i)) g(Index(j), xi, targets.positions[j]);
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
  // neighbours of x: one range per row of cells along axis 0 (consecutive in the CSR). With
  // cells smaller than the cutoff (grid.reach > 1) the cells whose nearest point is beyond
  // the cutoff are skipped, axis by axis (planes, then rows, then the ends of each row); the
  // test is in cell units with a padded radius (SearchGrid::stencil_radius), so it never
  // skips a neighbour. Positions outside the box walk the whole clamped stencil.
  template <class G>
  UNISPH_HOST_DEVICE void for_each_candidate_range(const Vec<T, D>& x, G&& g) const {
    const SearchGrid<T, D>& grid = targets.grid;
    const CellPlacement<D> placement = grid.place(x);
    if (placement.status & placement_non_finite) return;
    if (inner && targets.flag_outside && placement.status != placement_inside) return;
    const bool trim = grid.reach > 1 && placement.status == placement_inside;
    Vec<T, D> t;
    for (int a = 0; a < D; ++a) t[a] = trim ? grid.cell_coordinate(x, a) : T(0);
    const T radius2 = grid.stencil_radius * grid.stencil_radius;
    Vec<int, D> cell = placement.cell;
    const auto row = [&](T left2) {  // left2: the squared radius left after axes 1..D-1
      int first, last;
      axis_range(0, placement.cell[0], trim, t[0], left2, first, last);
      cell[0] = first;
      const Index first_cell = grid.linear_index(cell);
      g(targets.offsets[first_cell], targets.offsets[first_cell + static_cast<Index>(last - first) + 1]);
    };
    int y_first, y_last;
    if constexpr (D == 2) {
      axis_range(1, placement.cell[1], trim, t[1], radius2, y_first, y_last);
      for (int ky = y_first; ky <= y_last; ++ky) {
        cell[1] = ky;
        row(radius2 - gap_squared(trim, ky, t[1]));
      }
    } else {
      int z_first, z_last;
      axis_range(2, placement.cell[2], trim, t[2], radius2, z_first, z_last);
      for (int kz = z_first; kz <= z_last; ++kz) {
        cell[2] = kz;
        const T left_z = radius2 - gap_squared(trim, kz, t[2]);
        axis_range(1, placement.cell[1], trim, t[1], left_z, y_first, y_last);
        for (int ky = y_first; ky <= y_last; ++ky) {
          cell[1] = ky;
          row(left_z - gap_squared(trim, ky, t[1]));
        }
      }
    }
  }

  // The cells along axis a within `reach` of cell c and inside the grid; when trimming, only
  // those whose cell-unit interval [k, k + 1) comes within sqrt(left2) of t.
  UNISPH_HOST_DEVICE void axis_range(int a, int c, bool trim, T t, T left2, int& first, int& last) const {
    const SearchGrid<T, D>& grid = targets.grid;
    first = c - grid.reach > 0 ? c - grid.reach : 0;
    last = c + grid.reach < grid.cells[a] ? c + grid.reach : grid.cells[a] - 1;
    if (trim) {
      const T half = std::sqrt(left2 > T(0) ? left2 : T(0));
      const T lo = std::floor(t - half), hi = std::floor(t + half);
      if (lo > T(first)) first = static_cast<int>(lo);
      if (hi < T(last)) last = static_cast<int>(hi);
    }
  }

  // The squared distance in cell units from t to the cell interval [k, k + 1) (0 without trimming).
  UNISPH_HOST_DEVICE static T gap_squared(bool trim, int k, T t) {
    if (!trim) return T(0);
    const T below = T(k) - t, above = t - T(k + 1);
    const T gap = below > T(0) ? below : (above > T(0) ? above : T(0));
    return gap * gap;
  }
};

}  // namespace unisph
