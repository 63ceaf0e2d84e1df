#pragma once
// What dereferencing a view's iterator gives: one slot of a container, which may be empty
// (the free slots of a partly filled last frame, or a position past the end that a thread of
// a collective traversal visits so that every thread makes the same number of trips). The
// iterator cannot simply skip such slots: the element after an empty slot may be valid, and
// a collective traversal must keep its threads in step.
//
//   auto wrapper = *it;
//   if (wrapper) use(*wrapper);
//
// SlotRef<T> points at the element. ValueSlot<T> holds a value that names the element (a
// package's index, a data point's (package, local point)): the slot of a container whose
// elements are places of a structure rather than values in memory (package_traits.hpp), where
// there is nothing to point at. Both read the same way: `if (slot) use(*slot);`.

#include <type_traits>

#include "unisph/core/config.hpp"

namespace unisph::iter {

template <class T>
class SlotRef {
 public:
  using element_type = T;

  SlotRef() = default;
  UNISPH_HOST_DEVICE constexpr explicit SlotRef(T* element) : element_(element) {}

  // The slot of an element the view knows exists. It tells the compiler that the pointer is not
  // null, so that `if (slot)` in a loop body costs nothing for the slots of a filled block (nvcc
  // and GCC otherwise test every slot's pointer against null).
  UNISPH_HOST_DEVICE static constexpr SlotRef of(T& element) {
    T* p = &element;
#if defined(__CUDA_ARCH__)
    __builtin_assume(p != nullptr);
#elif defined(__GNUC__) || defined(__clang__)
    if (p == nullptr) __builtin_unreachable();
#endif
    return SlotRef(p);
  }

  // True when the slot holds an element.
  UNISPH_HOST_DEVICE constexpr explicit operator bool() const { return element_ != nullptr; }
  UNISPH_HOST_DEVICE constexpr bool valid() const { return element_ != nullptr; }
  // The element; only for a valid slot.
  UNISPH_HOST_DEVICE constexpr T& operator*() const { return *element_; }
  UNISPH_HOST_DEVICE constexpr T* operator->() const { return element_; }
  UNISPH_HOST_DEVICE constexpr T* get() const { return element_; }

  friend UNISPH_HOST_DEVICE constexpr bool operator==(SlotRef a, SlotRef b) { return a.element_ == b.element_; }

 private:
  T* element_ = nullptr;
};

static_assert(std::is_trivially_copyable_v<SlotRef<int>>);

template <class T>
class ValueSlot {
  static_assert(std::is_trivially_copyable_v<T>,
                "iter::ValueSlot<T>: the value that names an element is copied into device code, so it must be "
                "trivially copyable (an index, a small struct of indices).");

 public:
  using element_type = const T;

  ValueSlot() = default;
  // The slot of an element (a filled slot); ValueSlot() is an empty one.
  UNISPH_HOST_DEVICE static constexpr ValueSlot of(const T& value) {
    ValueSlot slot;
    slot.value_ = value;
    slot.valid_ = true;
    return slot;
  }

  UNISPH_HOST_DEVICE constexpr explicit operator bool() const { return valid_; }
  UNISPH_HOST_DEVICE constexpr bool valid() const { return valid_; }
  // The value; only for a valid slot.
  UNISPH_HOST_DEVICE constexpr const T& operator*() const { return value_; }
  UNISPH_HOST_DEVICE constexpr const T* operator->() const { return &value_; }

 private:
  T value_{};
  bool valid_ = false;
};

static_assert(std::is_trivially_copyable_v<ValueSlot<unsigned>>);

}  // namespace unisph::iter
