#pragma once
// Views over a cell linked list (neighbor/cell_linked_list.hpp): its cells, and one level down
// the particles of each cell (issue 8, part 3). Three containers, each with ContainerTraits:
//
//   CellParticles<T, D, Order>  the particles of one cell: the CSR places offsets[c] .. offsets[c + 1]
//   CellsOfList<T, D, Order>    every cell of a list, random access; child: CellParticles
//   CellBlock<T, D, Order>      a box of cells, axis 0 fastest (the 3^D cells around a particle's
//                               cell: neighbour iteration); child: CellParticles
//
// A particle slot yields the particle's position (const Vec<T, D>&); particle_index() gives
// its index back. Order says how the cell's places map to particles: through the list's
// `particles` array (CellOrder::indexed, any particle order), or, when the list was built from
// particles in cell order (CellListView::in_cell_order()), place k is particle k
// (CellOrder::contiguous: no indirection, ascending j). The two are different types so that
// the loop a view runs holds no test of the order; choose at run time, once, outside the loop.
//
// A cell's own element (what a cell-level view yields without a Child) is its entry in the CSR
// offsets: the place of its first particle.
//
// All handles are raw pointers and small numbers, trivially copyable, usable in device code.

#include <cstdint>
#include <type_traits>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/iter/container_traits.hpp"
#include "unisph/iter/slot_ref.hpp"
#include "unisph/neighbor/cell_linked_list.hpp"

namespace unisph::iter {

enum class CellOrder {
  indexed,     // the particles of place k: particles[k]
  contiguous,  // the particles are in cell order: place k is particle k
};

// What every cell-list container holds to reach the particles: raw pointers into one memory space.
template <class T, int D>
struct CellListArrays {
  const Vec<T, D>* positions = nullptr;
  const std::uint32_t* offsets = nullptr;    // cell_count + 2 (the cells, the flagged bucket, the end)
  const std::uint32_t* particles = nullptr;  // particle indices grouped by cell

  CellListArrays() = default;
  UNISPH_HOST_DEVICE CellListArrays(const Vec<T, D>* x, const std::uint32_t* o, const std::uint32_t* p)
      : positions(x), offsets(o), particles(p) {}
  // From the kernel-side view of a cell linked list.
  UNISPH_HOST_DEVICE explicit CellListArrays(const CellListView<T, D>& list)
      : positions(list.positions.data()), offsets(list.offsets.data()), particles(list.particles.data()) {}
};

// ---- the particles of one cell -----------------------------------------------------------------

template <class T, int D, CellOrder Order>
struct CellParticles {
  const Vec<T, D>* positions = nullptr;
  const std::uint32_t* particles = nullptr;  // unused for CellOrder::contiguous
  Index begin = 0;                           // the CSR places [begin, end)
  Index end = 0;
};

// The index of the particle a slot of a CellParticles view holds.
template <class T, int D>
UNISPH_HOST_DEVICE inline Index particle_index(const Vec<T, D>* positions, SlotRef<const Vec<T, D>> slot) {
  return Index(slot.get() - positions);
}

template <class T, int D, CellOrder Order>
struct ContainerTraits<CellParticles<T, D, Order>> : RandomAccessNavigation {
  using Handle = CellParticles<T, D, Order>;
  using Component = const Vec<T, D>;
  static constexpr bool needs_runtime_size = true;

  UNISPH_HOST_DEVICE static constexpr Handle empty_handle() { return Handle{}; }
  UNISPH_HOST_DEVICE static constexpr Index size(const Handle& h) { return h.end - h.begin; }
  UNISPH_HOST_DEVICE static constexpr Cursor start(const Handle& h, Index position, bool forward) {
    return start_at(size(h), position, forward);
  }
  UNISPH_HOST_DEVICE static constexpr Cursor step(const Handle&, Cursor cursor, Index k, bool forward) {
    return step_by(cursor, k, forward);
  }
  // Every place of a cell holds a particle (the view never dereferences past its count).
  UNISPH_HOST_DEVICE static constexpr bool holds_element(const Handle&, Cursor) { return true; }
  UNISPH_HOST_DEVICE static constexpr Index filled_prefix(const Handle& h) { return size(h); }
  UNISPH_HOST_DEVICE static constexpr Index slot_count(const Handle& h) { return size(h); }
  UNISPH_HOST_DEVICE static constexpr Component& element(const Handle& h, Cursor place) {
    if constexpr (Order == CellOrder::contiguous)
      return h.positions[h.begin + place];
    else
      return h.positions[h.particles[h.begin + place]];
  }
};

namespace detail {
template <class T, int D, CellOrder Order>
UNISPH_HOST_DEVICE inline CellParticles<T, D, Order> particles_of_cell(const CellListArrays<T, D>& a, Index cell) {
  return {a.positions, a.particles, Index(a.offsets[cell]), Index(a.offsets[cell + 1])};
}
}  // namespace detail

// ---- every cell of a list (random access) ----------------------------------------------------------

template <class T, int D, CellOrder Order>
struct CellsOfList {
  CellListArrays<T, D> arrays;
  Index cells = 0;  // the grid's cell count (the flagged bucket is not a cell)
};

template <class T, int D, CellOrder Order>
struct ContainerTraits<CellsOfList<T, D, Order>> : RandomAccessNavigation {
  using Handle = CellsOfList<T, D, Order>;
  using Component = const std::uint32_t;  // the cell's first place in the CSR
  using ChildContainer = CellParticles<T, D, Order>;
  static constexpr bool needs_runtime_size = true;

  UNISPH_HOST_DEVICE static constexpr Handle empty_handle() { return Handle{}; }
  UNISPH_HOST_DEVICE static constexpr Index size(const Handle& h) { return h.cells; }
  UNISPH_HOST_DEVICE static constexpr Cursor start(const Handle& h, Index position, bool forward) {
    return start_at(h.cells, position, forward);
  }
  UNISPH_HOST_DEVICE static constexpr Cursor step(const Handle&, Cursor cursor, Index k, bool forward) {
    return step_by(cursor, k, forward);
  }
  UNISPH_HOST_DEVICE static constexpr bool holds_element(const Handle&, Cursor) { return true; }
  UNISPH_HOST_DEVICE static constexpr Component& element(const Handle& h, Cursor cell) { return h.arrays.offsets[cell]; }
  UNISPH_HOST_DEVICE static constexpr ChildContainer child(const Handle& h, Cursor cell) {
    return detail::particles_of_cell<T, D, Order>(h.arrays, cell);
  }
};

// ---- a box of cells ------------------------------------------------------------------------------

// The cells lower .. lower + extent - 1 (per axis, inside the grid) of a list whose grid has
// grid_cells cells per axis, in the order of the linear cell index (axis 0 fastest): the order
// in which the direct search walks them.
template <class T, int D, CellOrder Order>
struct CellBlock {
  CellListArrays<T, D> arrays;
  Vec<int, D> grid_cells{};
  Vec<int, D> lower{};
  Vec<int, D> extent{};  // all zero: no cells

  // The cells within `reach` of `cell` along every axis, clipped to the grid.
  UNISPH_HOST_DEVICE static CellBlock around(const CellListArrays<T, D>& arrays, const Vec<int, D>& grid_cells,
                                             const Vec<int, D>& cell, int reach) {
    CellBlock b;
    b.arrays = arrays;
    b.grid_cells = grid_cells;
    for (int a = 0; a < D; ++a) {
      const int first = cell[a] - reach > 0 ? cell[a] - reach : 0;
      const int last = cell[a] + reach < grid_cells[a] ? cell[a] + reach : grid_cells[a] - 1;
      b.lower[a] = first;
      b.extent[a] = last >= first ? last - first + 1 : 0;
    }
    return b;
  }
};

// Where a walk over a block stands: the cell's place in the block and its linear index.
template <int D>
struct BlockCursor {
  Vec<int, D> offset{};  // 0 .. extent - 1 per axis
  Index cell = 0;        // linear index in the grid
};

template <class T, int D, CellOrder Order>
struct ContainerTraits<CellBlock<T, D, Order>> {
  using Handle = CellBlock<T, D, Order>;
  using Component = const std::uint32_t;  // the cell's first place in the CSR
  using ChildContainer = CellParticles<T, D, Order>;
  // Stepped, not computed from the position: a position -> cell map costs D - 1 divisions per
  // cell, a step one increment and, at the end of a row, a carry.
  using Cursor = BlockCursor<D>;
  static constexpr bool needs_runtime_size = true;

  UNISPH_HOST_DEVICE static constexpr Handle empty_handle() { return Handle{}; }
  UNISPH_HOST_DEVICE static constexpr Index size(const Handle& h) {
    Index n = 1;
    for (int a = 0; a < D; ++a) n *= Index(h.extent[a]);
    return n;
  }
  UNISPH_HOST_DEVICE static constexpr Index linear(const Handle& h, const Vec<int, D>& offset) {
    Index index = Index(h.lower[D - 1] + offset[D - 1]);
    for (int a = D - 2; a >= 0; --a) index = index * Index(h.grid_cells[a]) + Index(h.lower[a] + offset[a]);
    return index;
  }
  UNISPH_HOST_DEVICE static constexpr Cursor start(const Handle& h, Index position, bool forward) {
    Index p = forward ? position : size(h) - 1 - position;
    Cursor c;
    for (int a = 0; a < D; ++a) {
      c.offset[a] = int(p % Index(h.extent[a]));
      p /= Index(h.extent[a]);
    }
    c.cell = linear(h, c.offset);
    return c;
  }
  // One cell on along axis 0, carrying into the next row (and plane) at the end of one.
  // Views step only to positions inside the block.
  UNISPH_HOST_DEVICE static constexpr Cursor step(const Handle& h, Cursor c, Index k, bool forward) {
    for (; k > 0; --k) {
      Index stride = 1;
      for (int a = 0; a < D; ++a) {
        if (forward) {
          if (++c.offset[a] < h.extent[a]) {
            c.cell += stride;
            break;
          }
          c.offset[a] = 0;
          c.cell -= stride * Index(h.extent[a] - 1);
        } else {
          if (c.offset[a]-- > 0) {
            c.cell -= stride;
            break;
          }
          c.offset[a] = h.extent[a] - 1;
          c.cell += stride * Index(h.extent[a] - 1);
        }
        stride *= Index(h.grid_cells[a]);
      }
    }
    return c;
  }
  UNISPH_HOST_DEVICE static constexpr bool holds_element(const Handle&, const Cursor&) { return true; }
  UNISPH_HOST_DEVICE static constexpr Component& element(const Handle& h, const Cursor& c) {
    return h.arrays.offsets[c.cell];
  }
  UNISPH_HOST_DEVICE static constexpr ChildContainer child(const Handle& h, const Cursor& c) {
    return detail::particles_of_cell<T, D, Order>(h.arrays, c.cell);
  }
};

static_assert(std::is_trivially_copyable_v<CellBlock<float, 3, CellOrder::indexed>> &&
              std::is_trivially_copyable_v<CellParticles<float, 3, CellOrder::contiguous>> &&
              std::is_trivially_copyable_v<CellsOfList<double, 2, CellOrder::indexed>>);

}  // namespace unisph::iter
