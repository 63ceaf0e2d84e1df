#pragma once
// KernelShell<Method>: the kernel-shell layer of a method (seed 000). The method class holds
// its variables and parameters and defines
//
//   struct Kernel { ...views and plain values...; UNISPH_HOST_DEVICE ... };   // nested
//   Kernel make_kernel(KernelContext& context);                                 // views via context
//
// The shell builds the kernel on first use for a memory space, keeps it, and on every later
// launch re-establishes coherence for the variables it views (copying only what must be
// copied) and rebuilds it only when one of them was reallocated or resized. The kernel is
// then captured by value into the launch.
//
// Parameters copied into the kernel are fixed at build time: a value that changes between
// launches belongs in a SingularVariable (or is passed to exec, like dt), or the method calls
// invalidate_kernels() when it changes.

#include <any>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "unisph/dynamics/kernel_context.hpp"
#include "unisph/exec/policy.hpp"

namespace unisph {

template <class Method>
class KernelShell {
 public:
  // The kernel for the policy's memory space, built or refreshed as needed.
  template <ExecutionPolicy P>
  const auto& kernel(P) {
    using Kernel = typename Method::Kernel;
    static_assert(std::is_trivially_copyable_v<Kernel>,
                  "Method::Kernel is copied byte for byte into every launch (to the GPU as well), so it must be "
                  "trivially copyable: hold Views and plain values, not std::vector, references or virtual functions.");
    Slot& slot = slots_[static_cast<int>(P::space)];
    if (slot.kernel.has_value() && refresh(slot, P::space)) return *std::any_cast<Kernel>(&slot.kernel);
    KernelContext context(P::space);
    slot.kernel = static_cast<Method&>(*this).make_kernel(context);
    slot.uses = context.uses();
    ++slot.builds;
    return *std::any_cast<Kernel>(&slot.kernel);
  }

  // How many times the kernel for `space` was built (for tests and diagnostics).
  std::uint64_t kernel_builds(MemorySpace space) const { return slots_[static_cast<int>(space)].builds; }

  // Forces a rebuild at the next launch (after changing a parameter copied into the kernel).
  void invalidate_kernels() {
    for (Slot& s : slots_) s.kernel.reset();
  }

 protected:
  KernelShell() = default;
  // Copies would share nothing with the original's variables' stamps; methods are not copied.
  KernelShell(const KernelShell&) = delete;
  KernelShell& operator=(const KernelShell&) = delete;

 private:
  struct Slot {
    std::any kernel;
    std::vector<KernelContext::Use> uses;
    std::uint64_t builds = 0;
  };

  // Makes every viewed variable coherent for its access; false if a view went stale.
  static bool refresh(Slot& slot, MemorySpace space) {
    bool fresh = true;
    for (const KernelContext::Use& use : slot.uses) {
      use.variable->prepare(space, use.access);
      fresh = fresh && use.variable->layout_stamp(space) == use.stamp;
    }
    return fresh;
  }

  Slot slots_[2];
};

}  // namespace unisph
