#pragma once
// PeriodicCellWalk<T, D>: the kernel-side minimum-image neighbour search of a periodic domain by
// wrapped cell indices (issue 21; the other way is ghost images, periodic_images.hpp). A kernel
// holds one by value and calls
//
//   walk.for_each_neighbor(i, [&](Index j, const NeighborPair<T, D>& pair) { ... });
//
// as it would a NeighborSearch's direct search. The walk reads a cell linked list (the CSR of
// cell_linked_list.hpp, unchanged) whose grid divides every periodic axis exactly
// (SearchGrid::make_periodic: cells[a] cells of edge L_a / cells[a]), so that cell k + cells[a]
// along a periodic axis is cell k one period on. The stencil around x_i's cell is walked in
// *unwrapped* cell coordinates (along a periodic axis they may run below 0 or past the last
// cell):
//
//   planes (axis 2) and rows (axis 1)   the unwrapped index k taken modulo the cell count, with
//                                       the number of periods q it moved (k = w + q cells[a]);
//   the row along axis 0               split where it crosses a face into pieces, each one
//                                       contiguous CSR range [begin, end) with its own q;
//   the trimming of planes, rows and row ends (cells smaller than the cutoff) is that of the
//   direct search (stencil_traits.hpp), in the unwrapped coordinate.
//
// A range's candidates x_j stand for x_j + shift, shift_a = q_a L_a, so r_ij = x_i - x_j - shift.
// The walk computes it as (x_i - shift) - x_j: x_i - shift once per range (exactly x_i where
// q = 0), then the direct search's own pair test, so the innermost loop is the direct search's
// loop, and a pair that does not cross a face gets the direct search's bits.
//
// Requirements (checked by PeriodicCellList, periodic_cell_list.hpp, which hands these out):
//   * the box is at least two cutoffs wide along each periodic axis. Then at most one shift of a
//     candidate passes the cutoff test, even after rounding (the two shifts' components differ
//     by L >= 2 cutoff), so no pair is found twice, also where the grid has fewer than
//     2 reach + 1 cells along an axis and a row meets the same cell with two shifts;
//   * particles are inside the box along the periodic axes when the list is built and walked
//     (PeriodicCellList::wrap): a particle outside is clamped into a border cell and its
//     neighbours across the face may be missed.
// Non-periodic axes behave as in the direct search (clamped stencil, outside particles clamped or
// flagged, NaN has no neighbours). Stored lists, pair weights and relations are not wired to this
// walk: it is the direct search's counterpart, for measuring (docs/neighbor_search.md).

#include <cmath>
#include <cstdint>
#include <type_traits>

#include "unisph/core/config.hpp"
#include "unisph/core/uncontracted_arithmetic.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/neighbor/cell_linked_list.hpp"
#include "unisph/neighbor/neighbor_pair.hpp"
#include "unisph/neighbor/neighbor_search.hpp"

namespace unisph {

template <class T, int D>
struct PeriodicCellWalk {
  View<const Vec<T, D>> sources;  // x_i
  CellListView<T, D> targets;     // the x_j and their cells; targets.grid from SearchGrid::make_periodic
  bool inner;                     // sources are the targets: skip j == i

  // As NeighborSearch::source_in_cell_order / cell_order_source.
  UNISPH_HOST_DEVICE Index source_in_cell_order(Index k) const {
    return targets.in_cell_order() ? k : Index(targets.particles[k]);
  }
  UNISPH_HOST_DEVICE CellOrderSource cell_order_source(Index k) const { return {k, source_in_cell_order(k)}; }

  // f(j, pair) for every minimum-image neighbour j of source i, each once; pair.r_ij is the
  // minimum-image displacement x_i - x_j - shift.
  template <class F>
  UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void for_each_neighbor(Index i, F&& f) const {
    for_each_candidate(i, [&](Index j, const Vec<T, D>& xs, const Vec<T, D>& xj) {
      NeighborPair<T, D> pair;
      if (targets.grid.test_pair(xs, xj, pair.r_ij, pair.squared_distance)) {
        pair.complete();
        f(j, static_cast<const NeighborPair<T, D>&>(pair));
      }
    });
  }

  // As NeighborSearch::for_each_neighbor(CellOrderSource, f): where the list keeps its positions
  // in cell order (store_positions_in_cell_order) and the particles are not in cell order, x_i and
  // the candidates come from that copy (the positions at the build).
  template <class F>
  UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void for_each_neighbor(CellOrderSource s, F&& f) const {
    if (!inner || targets.points.empty() || targets.in_cell_order()) {
      for_each_neighbor(s.particle, f);
      return;
    }
    for_each_candidate_range(targets.points[s.slot].position(),
                             [&](std::uint32_t begin, std::uint32_t end, const Vec<T, D>& xs) {
                               for (std::uint32_t k = begin; k < end; ++k) {
                                 if (k == s.slot) continue;  // i itself (its images lie beyond the cutoff)
                                 NeighborPair<T, D> pair;
                                 if (targets.grid.test_pair(xs, targets.points[k].position(), pair.r_ij,
                                                            pair.squared_distance)) {
                                   pair.complete();
                                   f(Index(targets.particles[k]), static_cast<const NeighborPair<T, D>&>(pair));
                                 }
                               }
                             });
  }

  // g(j, xs, x_j) for every candidate j of i (j != i in an inner relation), xs = x_i - shift of
  // j's range; the cutoff test is g's. The two candidate loops of the direct search: contiguous
  // j where the particles are in cell order, through the CSR indices otherwise.
  template <class G>
  UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void for_each_candidate(Index i, G&& g) const {
    const bool cell_order = targets.in_cell_order();
    for_each_candidate_range(sources[i], [&](std::uint32_t begin, std::uint32_t end, const Vec<T, D>& xs) {
      if (cell_order) {
        for (std::uint32_t j = begin; j < end; ++j)
          if (!(inner && j == i)) g(Index(j), xs, targets.positions[j]);
      } else {
        for (std::uint32_t k = begin; k < end; ++k) {
          const Index j = targets.particles[k];
          if (!(inner && j == i)) g(j, xs, targets.positions[j]);
        }
      }
    });
  }

  // The particles a walk of i looks at (candidate pairs, for benchmarks).
  UNISPH_HOST_DEVICE Index candidate_count(Index i) const {
    Index count = 0;
    for_each_candidate_range(sources[i], [&](std::uint32_t begin, std::uint32_t end, const Vec<T, D>&) {
      count += end - begin;
    });
    return count;
  }

  // g(begin, end, xs) for each CSR range [begin, end) of targets.particles that can hold
  // minimum-image neighbours of x, xs = x - shift with the range's shift (see the header comment).
  // Planes, then rows, then the pieces of a row, in ascending unwrapped cell index.
  template <class G>
  UNISPH_HOST_DEVICE void for_each_candidate_range(const Vec<T, D>& x, G&& g) const {
    const SearchGrid<T, D>& grid = targets.grid;
    const CellPlacement<D> placement = grid.place(x);
    if (placement.status & placement_non_finite) return;
    if (inner && targets.flag_outside && placement.status != placement_inside) return;
    Stencil s;
    s.grid = &grid;
    s.cell = placement.cell;
    s.trim = grid.reach > 1 && placement.status == placement_inside;
    for (int a = 0; a < D; ++a) s.t[a] = s.trim ? grid.cell_coordinate(x, a) : T(0);
    const T radius2 = grid.stencil_radius * grid.stencil_radius;
    const std::uint32_t* offsets = targets.offsets.data();
    Vec<T, D> xs = x;
    int first, last;
    if constexpr (D == 2) {
      s.axis_range(1, radius2, first, last);
      for (int k1 = first; k1 <= last; ++k1) {
        const int w1 = s.wrapped(1, k1, x, xs);
        row(s, offsets, Index(w1) * Index(grid.cells[0]), radius2 - s.gap_squared(1, k1), x, xs, g);
      }
    } else {
      s.axis_range(2, radius2, first, last);
      for (int k2 = first; k2 <= last; ++k2) {
        const int w2 = s.wrapped(2, k2, x, xs);
        const T left2 = radius2 - s.gap_squared(2, k2);
        int first1, last1;
        s.axis_range(1, left2, first1, last1);
        for (int k1 = first1; k1 <= last1; ++k1) {
          const int w1 = s.wrapped(1, k1, x, xs);
          row(s, offsets, (Index(w2) * Index(grid.cells[1]) + Index(w1)) * Index(grid.cells[0]),
              left2 - s.gap_squared(1, k1), x, xs, g);
        }
      }
    }
  }

 private:
  // Where the stencil stands, and its arithmetic per axis (StencilCenter's, without clamping
  // along periodic axes).
  struct Stencil {
    const SearchGrid<T, D>* grid;
    Vec<int, D> cell;
    Vec<T, D> t;
    bool trim;

    // The unwrapped cells along axis a within reach of cell[a] (clamped into the grid along a
    // closed axis); when trimming, those whose interval [k, k + 1) comes within sqrt(left2) of t[a].
    UNISPH_HOST_DEVICE void axis_range(int a, T left2, int& first, int& last) const {
      const int c = cell[a];
      first = c - grid->reach;
      last = c + grid->reach;
      if (!grid->is_periodic(a)) {
        if (first < 0) first = 0;
        if (last > grid->cells[a] - 1) last = grid->cells[a] - 1;
      }
      if (trim) {
        const T half = std::sqrt(left2 > T(0) ? left2 : T(0));
        const T lo = std::floor(t[a] - half), hi = std::floor(t[a] + half);
        if (lo > T(first)) first = static_cast<int>(lo);
        if (hi < T(last)) last = static_cast<int>(hi);
      }
    }
    UNISPH_HOST_DEVICE T gap_squared(int a, int k) const {
      if (!trim) return T(0);
      const T below = T(k) - t[a], above = t[a] - T(k + 1);
      const T gap = below > T(0) ? below : (above > T(0) ? above : T(0));
      return gap * gap;
    }
    // The cell index in the grid of unwrapped index k along axis a, and xs[a] = x[a] - q L_a for
    // the q periods it moved (x[a] itself when q = 0; L_a = upper - lower of the grid's box).
    UNISPH_HOST_DEVICE int wrapped(int a, int k, const Vec<T, D>& x, Vec<T, D>& xs) const {
      if (!grid->is_periodic(a)) return k;
      const int n = grid->cells[a];
      int q = 0;
      while (k < 0) k += n, --q;
      while (k >= n) k -= n, ++q;
      const T length = uncontracted::sub(grid->box.upper[a], grid->box.lower[a]);
      xs[a] = q == 0 ? x[a] : uncontracted::sub(x[a], uncontracted::mul(T(q), length));
      return k;
    }
  };

  // The row of cells along axis 0 whose first cell of the grid's row is `base`: one range, or
  // along a periodic axis 0 one range per period it touches. One call of g (one inlined copy of
  // the candidate loop), with x_i's shifted copy for the range passed as a constant.
  template <class G>
  UNISPH_HOST_DEVICE static void row(const Stencil& s, const std::uint32_t* offsets, Index base, T left2,
                                     const Vec<T, D>& x, const Vec<T, D>& xs, G& g) {
    int first, last;
    s.axis_range(0, left2, first, last);
    const bool wraps = s.grid->is_periodic(0);
    const int n = s.grid->cells[0];
    for (int k = first; k <= last;) {
      Vec<T, D> shifted = xs;
      int w = k, count = last - k + 1;
      if (wraps) {
        w = s.wrapped(0, k, x, shifted);
        if (count > n - w) count = n - w;  // to the face
      }
      g(offsets[base + Index(w)], offsets[base + Index(w + count)], static_cast<const Vec<T, D>&>(shifted));
      k += count;
    }
  }
};

static_assert(std::is_trivially_copyable_v<PeriodicCellWalk<float, 3>> &&
              std::is_trivially_copyable_v<PeriodicCellWalk<double, 2>>);

}  // namespace unisph
