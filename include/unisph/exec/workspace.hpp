#pragma once
// WorkspaceScope: arrays that live only within one phase of a step (a sort's keys and
// permutation, a cell list's run arrays, a communication plan's lists), on every policy.
//
//   {
//     WorkspaceScope scope(policy);
//     View<std::uint64_t> keys = scope.take(policy, keys_, n);  // keys_: DiscreteVariable<std::uint64_t>
//     ...                                                       // kernels, sorts, scans on keys
//   }                                                           // released here
//
// On the device an array is a block of the device workspace (cuda::workspace_take, runtime.hpp):
// the blocks of one phase and the algorithms' temporaries above them share the memory that the
// next phase's blocks take again, so a run holds the most one phase needs at once instead of
// every phase's arrays for its whole length (about 50 bytes per particle on several ranks,
// docs/multi_gpu.md). On the host the array is the caller's variable, grown where needed and
// kept: host memory is not what limits a run, and keeping it allocates nothing per step.
//
// Scopes nest (the workspace is a stack); a scope's arrays are valid until it ends. Its contents
// start undefined on the device (the host variable keeps what it last held).

#include "unisph/exec/backend/cuda/runtime.hpp"
#include "unisph/exec/policy.hpp"
#include "unisph/memory/discrete_variable.hpp"

namespace unisph {

class WorkspaceScope {
 public:
  template <ExecutionPolicy P>
  explicit WorkspaceScope(P) : device_(P::space == MemorySpace::device) {
    if (device_) mark_ = cuda::workspace_mark();
  }
  ~WorkspaceScope() {
    if (device_) cuda::workspace_release(mark_);
  }
  WorkspaceScope(const WorkspaceScope&) = delete;
  WorkspaceScope& operator=(const WorkspaceScope&) = delete;

  // n elements in the policy's memory space for the scope's length; `host` is the storage on
  // the host and names the array on the device (in errors).
  template <ExecutionPolicy P, class T>
  View<T> take(P policy, DiscreteVariable<T>& host, Index n) {
    if constexpr (P::space == MemorySpace::device) {
      return View<T>(static_cast<T*>(cuda::workspace_take(n * sizeof(T), host.name())), n);
    } else {
      if (host.size() < n) host.resize(n);
      return host.read_write(policy).subview(0, n);
    }
  }

 private:
  bool device_;
  std::size_t mark_ = 0;
};

}  // namespace unisph
