#pragma once
// PointNeighbors<T, D>: the particles of a cell list within the cutoff of a point that is not a
// particle (a wave gauge's sample, a velocity probe), for the measurement kernels
// (wave_gauge.hpp, velocity_probe.hpp). A kernel holds one by value and calls
//
//   neighbors.for_each(x, [&](Index j, T r) { ... });   // every j with |x - x_j| < cutoff
//
// It walks the rows of cells of the direct search's stencil around x
// (NeighborSearch::for_each_candidate_range) and tests each candidate with the grid's own
// cutoff test (SearchGrid::test_pair: uncontracted, so every policy finds the same j), reading
// the positions as they are now. The cells are those of the list's last build: call after the
// list was built for the current positions, as the solver's observers run after its rebuild. (A
// particle that crossed a cell face since the build is still found while it moved less than
// the stencil's margin, as in the solver's own direct search.) Points outside the list's box
// walk the clamped border cells; a NaN coordinate has no neighbours.
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "unisph/dynamics/kernel_context.hpp"
#include "unisph/neighbor/cell_linked_list.hpp"
#include "unisph/neighbor/neighbor_search.hpp"

namespace unisph::sph {

template <class T, int D>
struct PointNeighbors {
  NeighborSearch<T, D> search;  // no sources; the targets are the cell list's particles

  // Views of the list's arrays and positions through a kernel shell's context.
  static PointNeighbors make(KernelContext& context, CellLinkedList<T, D>& cells) {
    PointNeighbors p{};
    p.search.targets = cells.view(context);
    p.search.inner = false;
    return p;
  }

  UNISPH_HOST_DEVICE T cutoff() const { return search.targets.grid.cutoff; }

  // f(j, |x - x_j|) for every particle j of the list closer than the cutoff, in the order of
  // the direct search (the same order on every policy for the same list).
  template <class F>
  UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void for_each(const Vec<T, D>& x, F&& f) const {
    const bool cell_order = search.targets.in_cell_order();
    search.for_each_candidate_range(x, [&](std::uint32_t begin, std::uint32_t end) {
      for (std::uint32_t k = begin; k < end; ++k) {
        const Index j = cell_order ? Index(k) : Index(search.targets.particles[k]);
        Vec<T, D> r;
        T r2;
        if (search.targets.grid.test_pair(x, search.targets.positions[j], r, r2)) f(j, std::sqrt(r2));
      }
    });
  }
};
static_assert(std::is_trivially_copyable_v<PointNeighbors<double, 3>>,
              "PointNeighbors is held by kernels that are copied to the device byte for byte.");

}  // namespace unisph::sph
