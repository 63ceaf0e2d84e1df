#pragma once
// The order in which a hierarchical view (iter::View) walks one level of a container.

#include <type_traits>

namespace unisph::iter::direction {

// First element first: slot 0 of a frame, the first frame of a supercell.
struct Forward {
  static constexpr bool is_forward = true;
};
// Last element first. Offsets, counts and jumps are counted in this order too, so offset 0
// is the last element and a count of k takes the last k elements.
struct Backward {
  static constexpr bool is_forward = false;
};

template <class D>
inline constexpr bool is_direction_v = std::is_same_v<D, Forward> || std::is_same_v<D, Backward>;

}  // namespace unisph::iter::direction
