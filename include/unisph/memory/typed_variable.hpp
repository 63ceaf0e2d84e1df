#pragma once
// The typed face shared by DiscreteVariable and SingularVariable: coherent views of T.

#include <string>
#include <type_traits>

#include "unisph/memory/space.hpp"
#include "unisph/memory/variable_base.hpp"
#include "unisph/memory/view.hpp"

namespace unisph {

template <class T>
inline constexpr bool is_variable_element_v =
    std::is_trivially_copyable_v<T> && std::is_trivially_default_constructible_v<T>;

template <class T>
class TypedVariable : public VariableBase {
  static_assert(is_variable_element_v<T>,
                "unisph variables copy T between host and device memory byte for byte and fill new elements with "
                "zero bytes, so T must be trivially copyable and trivially default constructible: plain numbers, "
                "unisph::Vec, unisph::Mat, or structs of them without constructors.");

 public:
  using value_type = T;

  // A coherent view of the copy in `space` for an access in `mode` (see VariableBase).
  View<T> view(MemorySpace space, Access mode) { return {static_cast<T*>(prepare(space, mode)), size()}; }
  View<const T> read(MemorySpace space) { return view(space, Access::read); }
  View<T> write(MemorySpace space) { return view(space, Access::write); }
  View<T> read_write(MemorySpace space) { return view(space, Access::read_write); }

  // The same, in the memory space of an execution policy (P::space).
  template <InMemorySpace P>
  View<T> view(P, Access mode) { return view(P::space, mode); }
  template <InMemorySpace P>
  View<const T> read(P) { return read(P::space); }
  template <InMemorySpace P>
  View<T> write(P) { return write(P::space); }
  template <InMemorySpace P>
  View<T> read_write(P) { return read_write(P::space); }

 protected:
  TypedVariable(std::string name, Index size) : VariableBase(std::move(name), sizeof(T), alignof(T), size) {}
};

}  // namespace unisph
