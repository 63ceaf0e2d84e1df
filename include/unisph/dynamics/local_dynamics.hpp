#pragma once
// The three method bases that later work builds on. Each is a KernelShell (see
// kernel_shell.hpp); the method defines a nested Kernel, make_kernel(KernelContext&) and
// size() (the number of items), and the base provides exec(policy, dt).
//
//   UpdateDynamics<M>        Kernel::update(i, dt)             writes item i from item i
//   InteractionDynamics<M>   Kernel::interaction(i, dt)        reads other items, writes item i only
//                                                               (neighbour relations plug in here)
//   ReduceDynamics<M, Op>    Kernel::reduce(i, dt) -> T         exec returns the Op-combination
//                                                               (passed through M::finish(T) if M has one)
//   ReduceDynamics<M, Op, ReduceOrder::fixed>                  the same with deterministic_reduce: the
//                                                               same bits on every policy (for results
//                                                               that steer a computation, e.g. FIRE's power)

#include <cstdint>
#include <type_traits>

#include "unisph/dynamics/kernel_shell.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/occupancy_hint.hpp"

namespace unisph {

namespace detail {
template <class Kernel>
struct UpdateLaunch {
  static constexpr int min_blocks_per_multiprocessor = unisph::min_blocks_per_multiprocessor<Kernel>();
  Kernel kernel;
  Real dt;
  UNISPH_HOST_DEVICE void operator()(Index i) const { kernel.update(i, dt); }
};
template <class Kernel>
struct InteractionLaunch {
  static constexpr int min_blocks_per_multiprocessor = unisph::min_blocks_per_multiprocessor<Kernel>();
  Kernel kernel;
  Real dt;
  UNISPH_HOST_DEVICE void operator()(Index i) const { kernel.interaction(i, dt); }
};
// The common case of a kernel compiled apart (see InteractionDynamics::exec).
template <class Kernel>
struct CommonCaseLaunch {
  static constexpr int min_blocks_per_multiprocessor = unisph::min_blocks_per_multiprocessor<Kernel>();
  Kernel kernel;
  Real dt;
  UNISPH_HOST_DEVICE void operator()(Index i) const { kernel.template interact<true>(i, dt); }
};
// A launch over a list of items: item items[k] for k in [0, items.size()).
template <class Launch>
struct ItemsLaunch {
  static constexpr int min_blocks_per_multiprocessor = Launch::min_blocks_per_multiprocessor;
  Launch launch;
  View<const std::uint32_t> items;
  UNISPH_HOST_DEVICE void operator()(Index k) const { launch(Index(items[k])); }
};
// A kernel's static case with the walk by runs (see InteractionDynamics::exec_items).
template <class Kernel>
struct StaticCaseLaunch {
  static constexpr int min_blocks_per_multiprocessor = unisph::min_blocks_per_multiprocessor<Kernel>();
  Kernel kernel;
  Real dt;
  UNISPH_HOST_DEVICE void operator()(Index i) const { kernel.template interact<true, true>(i, dt); }
};
template <class Kernel>
struct ReduceLaunch {
  static constexpr int min_blocks_per_multiprocessor = unisph::min_blocks_per_multiprocessor<Kernel>();
  Kernel kernel;
  Real dt;
  UNISPH_HOST_DEVICE auto operator()(Index i) const { return kernel.reduce(i, dt); }
};
}  // namespace detail

template <class Method>
class UpdateDynamics : public KernelShell<Method> {
 public:
  template <ExecutionPolicy P>
  void exec(P policy, Real dt = Real(0)) {
    using Kernel = typename Method::Kernel;
    const Kernel& k = this->kernel(policy);
    particle_for(policy, static_cast<const Method&>(*this).size(), detail::UpdateLaunch<Kernel>{k, dt});
  }
};

template <class Method>
class InteractionDynamics : public KernelShell<Method> {
 public:
  template <ExecutionPolicy P>
  void exec(P policy, Real dt = Real(0)) {
    using Kernel = typename Method::Kernel;
    const Kernel& k = this->kernel(policy);
    const Index n = static_cast<const Method&>(*this).size();
    // A kernel may compile its common case apart: with `bool common_case() const` and
    // `interact<true>(i, dt)` it leaves out the branches of rarer cases (moving walls, lists
    // walked by runs on several ranks), whose registers would spill in every case on the device.
    if constexpr (requires { k.common_case(); }) {
      if (k.common_case()) {
        particle_for(policy, n, detail::CommonCaseLaunch<Kernel>{k, dt});
        return;
      }
    }
    particle_for(policy, n, detail::InteractionLaunch<Kernel>{k, dt});
  }
  // The same for the items listed (each below size()), with the values exec() gives them: the
  // interactions of a subset, e.g. the interior particles while a halo's refresh is in flight.
  // Such subsets are a run on several ranks, whose lists are walked by runs: a kernel may compile
  // that case apart with `bool static_case() const` and `interact<true, true>(i, dt)` (static
  // walls, the walk by runs), instead of its one-rank common case.
  template <ExecutionPolicy P>
  void exec_items(P policy, View<const std::uint32_t> items, Real dt = Real(0)) {
    using Kernel = typename Method::Kernel;
    if (items.size() == 0) return;
    const Kernel& k = this->kernel(policy);
    if constexpr (requires { k.static_case(); }) {
      if (k.static_case()) {
        particle_for(policy, items.size(),
                     detail::ItemsLaunch<detail::StaticCaseLaunch<Kernel>>{{k, dt}, items});
        return;
      }
    } else if constexpr (requires { k.common_case(); }) {
      if (k.common_case()) {
        particle_for(policy, items.size(),
                     detail::ItemsLaunch<detail::CommonCaseLaunch<Kernel>>{{k, dt}, items});
        return;
      }
    }
    particle_for(policy, items.size(), detail::ItemsLaunch<detail::InteractionLaunch<Kernel>>{{k, dt}, items});
  }
  // The same for items whose neighbours all lie in other views of the neighbour lists than the
  // kernel's (the interior particles on several ranks see owned particles only, which a
  // cell-ordered view of them lists as on one rank): `retarget(kernel)` points a copy of the
  // kernel at those views, whose common case runs where it then holds, the general kernel
  // otherwise (the items' passes read those views only).
  template <ExecutionPolicy P, class Retarget>
  void exec_items_with(P policy, View<const std::uint32_t> items, Real dt, Retarget&& retarget) {
    using Kernel = typename Method::Kernel;
    if (items.size() == 0) return;
    Kernel k = this->kernel(policy);
    retarget(k);
    if constexpr (requires { k.common_case(); }) {
      if (k.common_case()) {
        particle_for(policy, items.size(), detail::ItemsLaunch<detail::CommonCaseLaunch<Kernel>>{{k, dt}, items});
        return;
      }
    }
    particle_for(policy, items.size(), detail::ItemsLaunch<detail::InteractionLaunch<Kernel>>{{k, dt}, items});
  }
};

// per_policy: particle_reduce (reproducible run to run on each policy); fixed: deterministic_reduce.
enum class ReduceOrder { per_policy, fixed };

template <class Method, class Op, ReduceOrder Order = ReduceOrder::per_policy>
class ReduceDynamics : public KernelShell<Method> {
 public:
  template <ExecutionPolicy P>
  auto exec(P policy, Real dt = Real(0)) {
    using Kernel = typename Method::Kernel;
    const Kernel& k = this->kernel(policy);
    const Index n = static_cast<const Method&>(*this).size();
    auto result = [&] {
      if constexpr (Order == ReduceOrder::fixed)
        return deterministic_reduce(policy, n, Op{}, detail::ReduceLaunch<Kernel>{k, dt});
      else
        return particle_reduce(policy, n, Op{}, detail::ReduceLaunch<Kernel>{k, dt});
    }();
    if constexpr (requires(Method& m) { m.finish(result); })
      return static_cast<Method&>(*this).finish(result);
    else
      return result;
  }
};

}  // namespace unisph
