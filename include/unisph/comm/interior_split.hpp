#pragma once
// InteriorSplit: a rank's owned particles split by whether a ghost can come within their reach
// before the next halo, so that their interactions can run while a halo's refresh is in flight.
//
// A particle is interior when its cell and the cell's 3^D neighbours are all this rank's and
// none lies across a periodic face (Decomposition::interior). Cells are at least cutoff + skin
// wide and particles move less than half the skin between two halo builds (the solver stops a
// run that would move more), so no ghost comes within the cutoff of an interior particle
// before the next build: its sums read owned particles only. The others are border particles.
// A decomposition that keeps no interior table (grids over 2^30 cells) makes every particle
// a border particle.
//
// With a reach (build's `reach` > 0: cutoff + skin), a particle of a cell next to another
// rank's cells is interior all the same where each such cell lies farther than the reach from
// it (and none lies across a periodic face): a ghost sits in its owner's cell at the halo's
// build, and the two particles close in by less than the skin before the next, so one farther
// than cutoff + skin never comes within the cutoff. The border is then a layer as thick as the
// reach instead of one or two cells (each at least the reach wide). Only for passes that read
// no ghost at all outside the cutoff (a cell list of the owned particles alone,
// CellLinkedList::owned_view): a walk of the whole list would visit ghosts being refreshed.
//
//   InteriorSplit<3> split;
//   split.build(policy, decomposition, owned_positions);      after each halo build
//   pass.exec_items(policy, split.interior(policy));          while the refresh is in flight
//   pass.exec_items(policy, split.border(policy));            after it
//
// items() lists the interior particles' indices ascending, then the border ones' ascending.
//
// Sources that call build() launch kernels: list them in unisph_kernel_sources().

#include <cstdint>

#include "unisph/comm/decomposition.hpp"
#include "unisph/comm/plan.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/workspace.hpp"
#include "unisph/memory/discrete_variable.hpp"

namespace unisph::comm {

namespace interior_detail {
// 1 where particle i is a border particle.
template <int D, class PS>
struct MarkBorder {
  DecompositionView<D> decomposition;
  View<const Vec<PS, D>> positions;
  View<std::uint32_t> border;
  Real reach;  // > 0: the other ranks' cells decide by their distance (see the header comment)
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    Vec<Real, D> x;
    for (int a = 0; a < D; ++a) x[a] = Real(positions[i][a]);
    const Vec<int, D> cell = decomposition.grid.cell_of(x);
    if (decomposition.is_interior(cell)) {
      border[i] = 0u;
      return;
    }
    border[i] = reach > 0 && !decomposition.interior.empty() && far_from_other_ranks(x, cell) ? 0u : 1u;
  }
  // Every neighbour cell of another rank farther than the reach from x, none across a periodic face.
  UNISPH_HOST_DEVICE bool far_from_other_ranks(const Vec<Real, D>& x, const Vec<int, D>& cell) const {
    const CellGrid<D>& grid = decomposition.grid;
    const int own = decomposition.owner_of_cell(cell);
    // Per axis, the distance from x to the faces of its cell below and above (0 if outside).
    Vec<Real, D> below, above;
    for (int a = 0; a < D; ++a) {
      const Real lower = grid.box.lower[a] + Real(cell[a]) * grid.cell_size[a];
      const Real b = x[a] - lower, u = lower + grid.cell_size[a] - x[a];
      below[a] = b > 0 ? b : Real(0);
      above[a] = u > 0 ? u : Real(0);
    }
    // A margin against the rounding of the cells' faces: a shorter reach never counts as far.
    const Real limit = reach * reach * Real(1.0001);
    int offsets = 1;
    for (int a = 0; a < D; ++a) offsets *= 3;
    for (int o = 0; o < offsets; ++o) {
      Vec<int, D> n;
      Real squared = 0;
      bool beyond = false;
      for (int a = 0, code = o; a < D; ++a, code /= 3) {
        const int step = code % 3 - 1;
        n[a] = cell[a] + step;
        if (n[a] < 0 || n[a] >= grid.cells[a]) {
          if (grid.periodic[a]) return false;  // an image across the face: left to the cells
          beyond = true;                        // no cell there
        }
        const Real d = step < 0 ? below[a] : step > 0 ? above[a] : Real(0);
        squared += d * d;
      }
      if (beyond || squared >= limit) continue;
      if (decomposition.owner_of_cell(n) != own) return false;
    }
    return true;
  }
};
// Particle i to its place: interior ones first, border ones after, each in index order.
struct PlaceSplit {
  View<const std::uint32_t> border_before;  // exclusive scan of the marks, n + 1 values
  View<std::uint32_t> items;
  Index n;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    const Index before = border_before[i];
    const bool border = border_before[i + 1] != border_before[i];
    const Index interior_count = n - Index(border_before[n]);
    items[border ? interior_count + before : i - before] = static_cast<std::uint32_t>(i);
  }
};
}  // namespace interior_detail

template <int D>
class InteriorSplit {
 public:
  // `positions`: the owned particles' positions in the policy's memory (float or double).
  // `reach` > 0 (cutoff + skin): the finer split of the header comment.
  template <ExecutionPolicy P, class PS>
  void build(P policy, const Decomposition<D>& decomposition, View<const Vec<PS, D>> positions, Real reach = 0) {
    const Index n = positions.size();
    items_.resize(n);
    if (n == 0) {
      interior_count_ = 0;
      return;
    }
    WorkspaceScope scope(policy);
    const View<std::uint32_t> marks = scope.take(policy, marks_, n);
    const View<std::uint32_t> before = scope.take(policy, before_, n + 1);
    particle_for(policy, n, interior_detail::MarkBorder<D, PS>{decomposition.view(policy), positions, marks, reach});
    exclusive_scan(policy, View<const std::uint32_t>(marks), before);
    particle_for(policy, n, interior_detail::PlaceSplit{before, items_.write(policy), n});
    particle_for(policy, 1, plan_detail::CopyElement{View<const std::uint32_t>(before), n, border_total_.write(policy)});
    interior_count_ = n - Index(border_total_.to_vector()[0]);
  }

  Index size() const { return items_.size(); }
  Index interior_count() const { return interior_count_; }
  Index border_count() const { return items_.size() - interior_count_; }
  template <ExecutionPolicy P>
  View<const std::uint32_t> items(P policy) {
    return items_.read(policy);
  }
  template <ExecutionPolicy P>
  View<const std::uint32_t> interior(P policy) {
    return items(policy).subview(0, interior_count_);
  }
  template <ExecutionPolicy P>
  View<const std::uint32_t> border(P policy) {
    return items(policy).subview(interior_count_, border_count());
  }

 private:
  DiscreteVariable<std::uint32_t> items_{"InteriorSplit.Items"};
  DiscreteVariable<std::uint32_t> marks_{"InteriorSplit.Marks"};
  DiscreteVariable<std::uint32_t> before_{"InteriorSplit.Before"};
  DiscreteVariable<std::uint32_t> border_total_{"InteriorSplit.BorderTotal", 1};
  Index interior_count_ = 0;
};

}  // namespace unisph::comm
