#pragma once
// A view is a raw pointer and a length into one memory space: what kernels hold.
// It owns nothing and is trivially copyable, so it can be captured by value into a launch.

#include <type_traits>

#include "unisph/core/config.hpp"

namespace unisph {

template <class T>
class View {
 public:
  using value_type = std::remove_const_t<T>;
  using element_type = T;

  View() = default;
  UNISPH_HOST_DEVICE constexpr View(T* data, Index size) : data_(data), size_(size) {}
  // A view of T converts to a view of const T (a write view can be read).
  template <class U, class = std::enable_if_t<std::is_same_v<const U, T> && !std::is_same_v<U, T>>>
  UNISPH_HOST_DEVICE constexpr View(const View<U>& other) : data_(other.data()), size_(other.size()) {}

  UNISPH_HOST_DEVICE constexpr T& operator[](Index i) const { return data_[i]; }
  UNISPH_HOST_DEVICE constexpr T* data() const { return data_; }
  UNISPH_HOST_DEVICE constexpr Index size() const { return size_; }
  UNISPH_HOST_DEVICE constexpr bool empty() const { return size_ == 0; }
  UNISPH_HOST_DEVICE constexpr T* begin() const { return data_; }
  UNISPH_HOST_DEVICE constexpr T* end() const { return data_ + size_; }
  // The sub-range [offset, offset + count).
  UNISPH_HOST_DEVICE constexpr View subview(Index offset, Index count) const { return View(data_ + offset, count); }

 private:
  T* data_ = nullptr;
  Index size_ = 0;
};

static_assert(std::is_trivially_copyable_v<View<double>>);

}  // namespace unisph
