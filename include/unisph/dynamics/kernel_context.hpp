#pragma once
// KernelContext: what a method's make_kernel() receives. Each variable it turns into a view is
// made coherent in the target memory space and recorded with its access mode, so that the
// method can later re-establish coherence and tell when the kernel's views went stale.

#include <cstdint>
#include <vector>

#include "unisph/memory/typed_variable.hpp"

namespace unisph {

class KernelContext {
 public:
  struct Use {
    VariableBase* variable;
    Access access;
    std::uint64_t stamp;  // layout stamp seen when the view was taken
  };

  explicit KernelContext(MemorySpace space) : space_(space) {}
  MemorySpace space() const { return space_; }

  template <class T>
  View<const T> read(TypedVariable<T>& v) {
    View<const T> view = v.read(space_);
    record(v, Access::read);
    return view;
  }
  template <class T>
  View<T> write(TypedVariable<T>& v) {
    View<T> view = v.write(space_);
    record(v, Access::write);
    return view;
  }
  template <class T>
  View<T> read_write(TypedVariable<T>& v) {
    View<T> view = v.read_write(space_);
    record(v, Access::read_write);
    return view;
  }

  const std::vector<Use>& uses() const { return uses_; }

 private:
  void record(VariableBase& v, Access access) { uses_.push_back({&v, access, v.layout_stamp(space_)}); }

  MemorySpace space_;
  std::vector<Use> uses_;
};

}  // namespace unisph
