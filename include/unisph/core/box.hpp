#pragma once
// An axis-aligned box [lower, upper] (both faces included): the region a cell linked list covers.

#include <string>

#include "unisph/core/vector.hpp"

namespace unisph {

template <class T, int D>
struct Box {
  Vec<T, D> lower;
  Vec<T, D> upper;

  UNISPH_HOST_DEVICE constexpr bool contains(const Vec<T, D>& x) const {
    for (int a = 0; a < D; ++a)
      if (!(lower[a] <= x[a] && x[a] <= upper[a])) return false;  // NaN is outside
    return true;
  }
  UNISPH_HOST_DEVICE constexpr Vec<T, D> extent() const { return upper - lower; }
};

template <class T, int D>
std::string to_string(const Box<T, D>& box) {
  std::string s = "[";
  for (int a = 0; a < D; ++a) s += (a ? ", " : "") + std::to_string(box.lower[a]);
  s += "] to [";
  for (int a = 0; a < D; ++a) s += (a ? ", " : "") + std::to_string(box.upper[a]);
  return s + "]";
}

}  // namespace unisph
