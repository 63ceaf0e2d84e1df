#pragma once
// 64-bit Morton keys of cell coordinates: the bits of the coordinates interleaved (axis 0 in
// the lowest bit), so that cells close in space get close keys. 21 bits per axis: 42 bits in
// 2D, 63 in 3D — distinct keys for every cell of a grid of up to 2^21 cells per axis.

#include <cstdint>

#include "unisph/core/vector.hpp"

namespace unisph {

// The lowest 21 bits of v spread to every third bit (bit b goes to bit 3b).
UNISPH_HOST_DEVICE constexpr std::uint64_t spread_bits_by_3(std::uint64_t v) {
  v &= 0x1fffffull;
  v = (v | (v << 32)) & 0x001f00000000ffffull;
  v = (v | (v << 16)) & 0x001f0000ff0000ffull;
  v = (v | (v << 8)) & 0x100f00f00f00f00full;
  v = (v | (v << 4)) & 0x10c30c30c30c30c3ull;
  v = (v | (v << 2)) & 0x1249249249249249ull;
  return v;
}

// The lowest 21 bits of v spread to every second bit (bit b goes to bit 2b).
UNISPH_HOST_DEVICE constexpr std::uint64_t spread_bits_by_2(std::uint64_t v) {
  v &= 0x1fffffull;
  v = (v | (v << 16)) & 0x0000ffff0000ffffull;
  v = (v | (v << 8)) & 0x00ff00ff00ff00ffull;
  v = (v | (v << 4)) & 0x0f0f0f0f0f0f0f0full;
  v = (v | (v << 2)) & 0x3333333333333333ull;
  v = (v | (v << 1)) & 0x5555555555555555ull;
  return v;
}

template <int D>
UNISPH_HOST_DEVICE constexpr std::uint64_t morton_key(const Vec<int, D>& cell) {
  static_assert(D == 2 || D == 3, "Morton keys are defined here for 2D and 3D cells.");
  if constexpr (D == 2) {
    return spread_bits_by_2(static_cast<std::uint64_t>(cell[0])) |
           (spread_bits_by_2(static_cast<std::uint64_t>(cell[1])) << 1);
  } else {
    return spread_bits_by_3(static_cast<std::uint64_t>(cell[0])) |
           (spread_bits_by_3(static_cast<std::uint64_t>(cell[1])) << 1) |
           (spread_bits_by_3(static_cast<std::uint64_t>(cell[2])) << 2);
  }
}

// The number of key bits that can be non-zero for cell coordinates below `cells_per_axis`
// (sorting only those bits saves radix passes).
constexpr int morton_key_bits(int dimension, int cells_per_axis) {
  int bits = 0;
  while ((1ll << bits) < cells_per_axis) ++bits;
  return dimension * bits;
}

}  // namespace unisph
