#pragma once
// Views over the stencil of a direct neighbour search (issue 8, part 3): the cells that can hold
// neighbours of a position x, as the hierarchy the search walks.
//
//   StencilPlanes<T, 3>         the planes of cells (along axis 2) of the stencil   child: StencilRows
//   StencilRows<T, D>           the rows of cells (along axis 1) of a plane (in 2D:  child: RowPlaces
//                               of the stencil)
//   RowPlaces<T, D>             the CSR places of one row of cells
//
// A row is the unit because consecutive cells along axis 0 are consecutive places of the cell
// list's CSR: the particles of a whole row are one contiguous range, walked by one plain loop
// (9 row loops in 3D for cells of the cutoff, not 27 cell loops with their own bounds; docs/views.md
// measured the cell-by-cell walk 25-30 % slower inside the GPU SPH kernels).
//
// With cells smaller than the cutoff (reach > 1) and x inside the box, each level is trimmed to
// the cells that come within the cutoff (SearchGrid::stencil_radius, in cell units, padded so that
// no neighbour is ever skipped): the planes, then per plane the rows, then per row its ends. Each
// level's element count is known when its view starts (the view needs it for its trip count);
// the trimming of a level below is computed when the parent hands it its element.
//
// The engine (NeighborSearch::for_each_stencil_row) walks the planes and rows with these views and
// each row's places, one contiguous range [begin, end) of the list's CSR, as a counted loop: walked
// as a view of its own (RowPlaces' slots with a reader of j and x_j), the rows measured 7 to 18 %
// slower in neighbor_bench's GPU density pass on an H100 (docs/views.md).
//
// Every level walks with 32-bit positions (small_positions): on the GPU a 64-bit loop counter
// costs two instructions per step and per compare, and two registers.

#include <cmath>
#include <cstdint>
#include <type_traits>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/neighbor/cell_list_traits.hpp"
#include "unisph/iter/container_traits.hpp"
#include "unisph/iter/runtime.hpp"
#include "unisph/iter/slot_ref.hpp"
#include "unisph/iter/view.hpp"
#include "unisph/neighbor/cell_linked_list.hpp"

namespace unisph::iter {

// The cell list a stencil walk reads, by pointer: the kernel-side CellListView the search holds
// (in device code, inside the kernel's parameters). Copying its arrays' pointers and the grid's
// sizes into the walk's handles kept them in registers for the whole walk (3D double pressure
// relaxation: 105 registers against 80, ptxas -v); read through the pointer, they stay
// parameters the compiler loads where they are used.
template <class T, int D>
struct StencilArrays {
  const CellListView<T, D>* list = nullptr;
  UNISPH_HOST_DEVICE const Vec<T, D>* positions() const { return list->positions.data(); }
  UNISPH_HOST_DEVICE const std::uint32_t* offsets() const { return list->offsets.data(); }
  UNISPH_HOST_DEVICE const std::uint32_t* particles() const { return list->particles.data(); }
};

// Where the stencil stands: what every level needs to find and trim its cells. The arithmetic of
// axis_range and gap_squared is the direct search's since its first version (the same cells, so
// the same pairs in the same order, bit for bit).
template <class T, int D>
struct StencilCenter {
  const SearchGrid<T, D>* grid = nullptr;
  Vec<int, D> cell{};  // the cell of x (clamped into the whole grid where x is outside the box)
  Vec<T, D> t{};       // x in cell units (trimming only)
  bool trim = false;

  // The cells along axis a within `reach` of cell[a] and inside the grid; when trimming, only
  // those whose cell-unit interval [k, k + 1) comes within sqrt(left2) of t[a].
  UNISPH_HOST_DEVICE void axis_range(int a, T left2, int& first, int& last) const {
    const int c = cell[a];
    first = c - grid->reach > 0 ? c - grid->reach : 0;
    last = c + grid->reach < grid->cells[a] ? c + grid->reach : grid->cells[a] - 1;
    if (trim) {
      const T half = std::sqrt(left2 > T(0) ? left2 : T(0));
      const T lo = std::floor(t[a] - half), hi = std::floor(t[a] + half);
      if (lo > T(first)) first = static_cast<int>(lo);
      if (hi < T(last)) last = static_cast<int>(hi);
    }
    // A sub-grid's stencil around a cell beyond it (SearchGrid::sub_grid): empty, at a place
    // within the table.
    if (first > grid->cells[a]) first = grid->cells[a];
    if (last < first - 1) last = first - 1;
  }
  // The squared distance in cell units from t[a] to the cell interval [k, k + 1) (0 without trimming).
  UNISPH_HOST_DEVICE T gap_squared(int a, int k) const {
    if (!trim) return T(0);
    const T below = T(k) - t[a], above = t[a] - T(k + 1);
    const T gap = below > T(0) ? below : (above > T(0) ? above : T(0));
    return gap * gap;
  }
};

// ---- the places of one row -------------------------------------------------------------------

template <class T, int D>
struct RowPlaces {
  const std::uint32_t* particles = nullptr;
  std::uint32_t begin = 0, end = 0;  // the CSR places [begin, end)
};

template <class T, int D>
struct ContainerTraits<RowPlaces<T, D>> : RandomAccessNavigation {
  using Handle = RowPlaces<T, D>;
  using Component = const std::uint32_t;  // the place's particle index
  static constexpr bool needs_runtime_size = true;
  static constexpr bool small_positions = true;
  static constexpr bool every_slot_filled = true;

  UNISPH_HOST_DEVICE static constexpr Handle empty_handle() { return Handle{}; }
  UNISPH_HOST_DEVICE static constexpr Index size(const Handle& h) { return h.end - h.begin; }
  UNISPH_HOST_DEVICE static constexpr Cursor start(const Handle& h, Index position, bool forward) {
    return start_at(size(h), position, forward);
  }
  UNISPH_HOST_DEVICE static constexpr Cursor step(const Handle&, Cursor cursor, Index k, bool forward) {
    return step_by(cursor, k, forward);
  }
  UNISPH_HOST_DEVICE static constexpr bool holds_element(const Handle&, Cursor) { return true; }
  UNISPH_HOST_DEVICE static constexpr Component& element(const Handle& h, Cursor place) {
    return h.particles[h.begin + std::uint32_t(place)];
  }
};

// ---- the rows of a plane ---------------------------------------------------------------------

template <class T, int D>
struct StencilRows {
  StencilArrays<T, D> arrays;
  StencilCenter<T, D> center;
  int plane = 0;     // the plane's index along axis 2 (3D)
  T left2 = T(0);    // the squared radius left for axes 0 and 1
  int first_row = 0;
  int rows = 0;
};

template <class T, int D>
struct ContainerTraits<StencilRows<T, D>> : RandomAccessNavigation {
  using Handle = StencilRows<T, D>;
  using Component = const std::uint32_t;  // the row's first place in the CSR
  using ChildContainer = RowPlaces<T, D>;
  static constexpr bool needs_runtime_size = true;
  static constexpr bool small_positions = true;
  static constexpr bool every_slot_filled = true;

  UNISPH_HOST_DEVICE static constexpr Handle empty_handle() { return Handle{}; }
  UNISPH_HOST_DEVICE static constexpr Index size(const Handle& h) { return Index(h.rows); }
  UNISPH_HOST_DEVICE static constexpr Cursor start(const Handle& h, Index position, bool forward) {
    return start_at(size(h), position, forward);
  }
  UNISPH_HOST_DEVICE static constexpr Cursor step(const Handle&, Cursor cursor, Index k, bool forward) {
    return step_by(cursor, k, forward);
  }
  UNISPH_HOST_DEVICE static constexpr bool holds_element(const Handle&, Cursor) { return true; }

  // The row's cells along axis 0 (trimmed with what is left of the radius after axis 1) and the
  // linear index of its first cell.
  UNISPH_HOST_DEVICE static Index first_cell(const Handle& h, Cursor row, int& length) {
    const int ky = h.first_row + int(row);
    int first, last;
    h.center.axis_range(0, h.left2 - h.center.gap_squared(1, ky), first, last);
    length = last - first + 1;
    Index index = D == 3 ? Index(h.plane) * Index(h.center.grid->cells[1]) + Index(ky) : Index(ky);
    return index * Index(h.center.grid->cells[0]) + Index(first);
  }
  UNISPH_HOST_DEVICE static Component& element(const Handle& h, Cursor row) {
    int length;
    return h.arrays.offsets()[first_cell(h, row, length)];
  }
  UNISPH_HOST_DEVICE static ChildContainer child(const Handle& h, Cursor row) {
    int length;
    const Index cell = first_cell(h, row, length);
    return {h.arrays.particles(), h.arrays.offsets()[cell], h.arrays.offsets()[cell + static_cast<Index>(length)]};
  }
};

// ---- the planes of a 3D stencil ----------------------------------------------------------------

template <class T, int D>
struct StencilPlanes {
  static_assert(D == 3, "iter::StencilPlanes: only a 3D stencil has planes; a 2D stencil starts at StencilRows.");
  StencilArrays<T, D> arrays;
  StencilCenter<T, D> center;
  T radius2 = T(0);  // the squared stencil radius in cell units
  int first_plane = 0;
  int planes = 0;
};

template <class T, int D>
struct ContainerTraits<StencilPlanes<T, D>> : RandomAccessNavigation {
  using Handle = StencilPlanes<T, D>;
  using Component = const std::uint32_t;  // the plane's first place in the CSR
  using ChildContainer = StencilRows<T, D>;
  static constexpr bool needs_runtime_size = true;
  static constexpr bool small_positions = true;
  static constexpr bool every_slot_filled = true;

  UNISPH_HOST_DEVICE static constexpr Handle empty_handle() { return Handle{}; }
  UNISPH_HOST_DEVICE static constexpr Index size(const Handle& h) { return Index(h.planes); }
  UNISPH_HOST_DEVICE static constexpr Cursor start(const Handle& h, Index position, bool forward) {
    return start_at(size(h), position, forward);
  }
  UNISPH_HOST_DEVICE static constexpr Cursor step(const Handle&, Cursor cursor, Index k, bool forward) {
    return step_by(cursor, k, forward);
  }
  UNISPH_HOST_DEVICE static constexpr bool holds_element(const Handle&, Cursor) { return true; }
  // The plane's rows, trimmed with what is left of the radius after axis 2.
  UNISPH_HOST_DEVICE static ChildContainer child(const Handle& h, Cursor plane) {
    ChildContainer rows;
    rows.arrays = h.arrays;
    rows.center = h.center;
    rows.plane = h.first_plane + int(plane);
    rows.left2 = h.radius2 - h.center.gap_squared(2, rows.plane);
    int last;
    h.center.axis_range(1, rows.left2, rows.first_row, last);
    rows.rows = last >= rows.first_row ? last - rows.first_row + 1 : 0;
    return rows;
  }
  UNISPH_HOST_DEVICE static Component& element(const Handle& h, Cursor plane) {
    const ChildContainer rows = child(h, plane);
    return ContainerTraits<ChildContainer>::element(rows, 0);
  }
};

// ---- the whole stencil ---------------------------------------------------------------------------

// The view of the stencil around x: planes -> rows -> places in 3D, rows -> places in 2D; one
// worker, offset 0 and jump 1 at every level (CompileTimeTuple<>), so no position is padding
// and a loop body needs no slot test.
template <class T, int D>
struct StencilView;
template <class T>
struct StencilView<T, 2> {
  using Places = View<RowPlaces<T, 2>, direction::Forward, collectivity::None, CompileTimeTuple<>>;
  using type = View<StencilRows<T, 2>, direction::Forward, collectivity::None, CompileTimeTuple<>, Places>;
};
template <class T>
struct StencilView<T, 3> {
  using Places = View<RowPlaces<T, 3>, direction::Forward, collectivity::None, CompileTimeTuple<>>;
  using Rows = View<StencilRows<T, 3>, direction::Forward, collectivity::None, CompileTimeTuple<>, Places>;
  using type = View<StencilPlanes<T, 3>, direction::Forward, collectivity::None, CompileTimeTuple<>, Rows>;
};
template <class T, int D>
using stencil_view_t = typename StencilView<T, D>::type;
template <class T, int D>
using row_view_t = typename StencilView<T, D>::Places;

// The stencil of a position whose placement in `grid` is `placement` (not non-finite). Where x is
// inside the box and the cells are smaller than the cutoff, trimmed; otherwise the whole clamped
// (2 reach + 1)^D block.
template <class T, int D>
UNISPH_HOST_DEVICE inline stencil_view_t<T, D> stencil_around(const SearchGrid<T, D>& grid, const StencilArrays<T, D>& arrays,
                                                              const CellPlacement<D>& placement, const Vec<T, D>& x) {
  StencilCenter<T, D> center;
  center.grid = &grid;
  center.cell = placement.cell;
  center.trim = grid.reach > 1 && placement.status == placement_inside;
  for (int a = 0; a < D; ++a) center.t[a] = center.trim ? grid.cell_coordinate(x, a) : T(0);
  const T radius2 = grid.stencil_radius * grid.stencil_radius;
  int first, last;
  center.axis_range(D - 1, radius2, first, last);
  const int count = last >= first ? last - first + 1 : 0;
  using V = stencil_view_t<T, D>;
  if constexpr (D == 2) {
    StencilRows<T, D> rows;
    rows.arrays = arrays;
    rows.center = center;
    rows.left2 = radius2;
    rows.first_row = first;
    rows.rows = count;
    return V(rows);
  } else {
    StencilPlanes<T, D> planes;
    planes.arrays = arrays;
    planes.center = center;
    planes.radius2 = radius2;
    planes.first_plane = first;
    planes.planes = count;
    return V(planes);
  }
}

// g(row) for the view of each row of the stencil (its CSR places), row after row.
template <class T, int D, class G>
UNISPH_HOST_DEVICE inline void for_each_row(const stencil_view_t<T, D>& stencil, G&& g) {
  if constexpr (D == 2)
    stencil.for_each_child(g);
  else
    stencil.for_each_child([&](const typename StencilView<T, D>::Rows& rows) { rows.for_each_child(g); });
}

static_assert(std::is_trivially_copyable_v<StencilPlanes<float, 3>> && std::is_trivially_copyable_v<StencilRows<double, 2>> &&
              std::is_trivially_copyable_v<RowPlaces<float, 3>>);

}  // namespace unisph::iter
