#pragma once
// Reduction operations for particle_reduce: each carries its identity, so that an empty range
// reduces to it. Min and Max work on scalars and componentwise on unisph::Vec.
// A user operation is any associative callable `T op(T, T)`; pass its identity explicitly.

#include <limits>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"

namespace unisph {

namespace detail {
template <class T>
struct ScalarLimits {
  UNISPH_HOST_DEVICE static constexpr T lowest() { return std::numeric_limits<T>::lowest(); }
  UNISPH_HOST_DEVICE static constexpr T highest() {
    if constexpr (std::numeric_limits<T>::has_infinity)
      return std::numeric_limits<T>::infinity();
    else
      return std::numeric_limits<T>::max();
  }
};
template <class T>
struct Limits {
  UNISPH_HOST_DEVICE static constexpr T lowest() {
    if constexpr (std::numeric_limits<T>::has_infinity)
      return -std::numeric_limits<T>::infinity();
    else
      return std::numeric_limits<T>::lowest();
  }
  UNISPH_HOST_DEVICE static constexpr T highest() { return ScalarLimits<T>::highest(); }
};
template <class T, int D>
struct Limits<Vec<T, D>> {
  UNISPH_HOST_DEVICE static constexpr Vec<T, D> lowest() { return Vec<T, D>::constant(Limits<T>::lowest()); }
  UNISPH_HOST_DEVICE static constexpr Vec<T, D> highest() { return Vec<T, D>::constant(Limits<T>::highest()); }
};
}  // namespace detail

template <class T>
struct Sum {
  UNISPH_HOST_DEVICE static constexpr T identity() { return T{}; }
  UNISPH_HOST_DEVICE constexpr T operator()(const T& a, const T& b) const { return a + b; }
};

template <class T>
struct Min {
  UNISPH_HOST_DEVICE static constexpr T identity() { return detail::Limits<T>::highest(); }
  UNISPH_HOST_DEVICE constexpr T operator()(const T& a, const T& b) const {
    if constexpr (requires { T::size; }) {
      return unisph::min(a, b);
    } else {
      return b < a ? b : a;
    }
  }
};

template <class T>
struct Max {
  UNISPH_HOST_DEVICE static constexpr T identity() { return detail::Limits<T>::lowest(); }
  UNISPH_HOST_DEVICE constexpr T operator()(const T& a, const T& b) const {
    if constexpr (requires { T::size; }) {
      return unisph::max(a, b);
    } else {
      return a < b ? b : a;
    }
  }
};

// An operation whose identity is known (Sum, Min, Max or a user type with `identity()`).
template <class Op, class T>
concept ReductionWithIdentity = requires(const Op& op, const T& a) {
  { Op::identity() };
  { op(a, a) };
};

}  // namespace unisph
