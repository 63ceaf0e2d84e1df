#pragma once
// partition_point(first, last, below): the first index in [first, last) at which `below` is
// false, for a predicate that is true on a leading part of the range and false after it
// (std::partition_point over indices rather than iterators), on the host and in device code.
// A lower bound is below(i) = a[i] < key; an upper bound is below(i) = a[i] <= key.

#include "unisph/core/config.hpp"

namespace unisph {

template <class I, class Below>
UNISPH_HOST_DEVICE constexpr I partition_point(I first, I last, Below below) {
  while (first < last) {
    const I mid = first + (last - first) / 2;
    if (below(mid)) first = mid + 1;
    else last = mid;
  }
  return first;
}

}  // namespace unisph
