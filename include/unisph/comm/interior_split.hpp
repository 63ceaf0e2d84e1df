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
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    Vec<Real, D> x;
    for (int a = 0; a < D; ++a) x[a] = Real(positions[i][a]);
    border[i] = decomposition.is_interior(decomposition.grid.cell_of(x)) ? 0u : 1u;
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
  template <ExecutionPolicy P, class PS>
  void build(P policy, const Decomposition<D>& decomposition, View<const Vec<PS, D>> positions) {
    const Index n = positions.size();
    items_.resize(n);
    if (n == 0) {
      interior_count_ = 0;
      return;
    }
    WorkspaceScope scope(policy);
    const View<std::uint32_t> marks = scope.take(policy, marks_, n);
    const View<std::uint32_t> before = scope.take(policy, before_, n + 1);
    particle_for(policy, n, interior_detail::MarkBorder<D, PS>{decomposition.view(policy), positions, marks});
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
