#pragma once
// DiscreteVariable<T>: a named per-item array (one value per particle, cell or package) with a
// host copy and a device copy kept coherent by the accesses made through it (VariableBase).

#include <initializer_list>
#include <span>
#include <string>
#include <vector>

#include "unisph/memory/typed_variable.hpp"

namespace unisph {

template <class T>
class DiscreteVariable : public TypedVariable<T> {
 public:
  explicit DiscreteVariable(std::string name, Index size = 0) : TypedVariable<T>(std::move(name), size) {}
  DiscreteVariable(std::string name, std::initializer_list<T> values) : DiscreteVariable(std::move(name)) {
    assign(std::span<const T>(values.begin(), values.size()));
  }

  // Resizes, keeping the contents where they are current; new elements are T{} (zero).
  void resize(Index size) { this->resize_elements(size); }

  // Host conveniences.
  void assign(std::span<const T> values) {
    resize(values.size());
    View<T> host = this->write(MemorySpace::host);
    for (Index i = 0; i < values.size(); ++i) host[i] = values[i];
  }
  std::vector<T> to_vector() {
    View<const T> host = this->read(MemorySpace::host);
    return std::vector<T>(host.begin(), host.end());
  }
};

}  // namespace unisph
