#pragma once
// SingularVariable<T>: one named value (a particle count, the physical time, a maximum speed)
// with the same host/device coherence as DiscreteVariable. Kernels see it as a one-element view.

#include <string>

#include "unisph/memory/typed_variable.hpp"

namespace unisph {

template <class T>
class SingularVariable : public TypedVariable<T> {
 public:
  explicit SingularVariable(std::string name, const T& initial = T{}) : TypedVariable<T>(std::move(name), 1) {
    set(initial);
  }

  // The current value (waits for the device if it holds the latest one).
  T get() { return this->read(MemorySpace::host)[0]; }
  void set(const T& value) { this->write(MemorySpace::host)[0] = value; }
};

}  // namespace unisph
