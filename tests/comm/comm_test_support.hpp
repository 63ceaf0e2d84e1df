#pragma once
// Shared by the communication tests: a global particle set made from a seed (the same on
// every rank), and the slice of it a rank starts with.
#include <cstdint>
#include <random>
#include <vector>

#include "unisph/comm/communicator.hpp"
#include "unisph/core/vector.hpp"

namespace unisph::comm_test {

template <int D>
std::vector<Vec<Real, D>> global_positions(std::size_t n, std::uint32_t seed, Real lower = 0, Real upper = 1) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lower, upper);
  std::vector<Vec<Real, D>> x(n);
  for (auto& p : x)
    for (int a = 0; a < D; ++a) p[a] = static_cast<Real>(u(rng));
  // Particles at the box's corners (just inside), where a ghost goes to the most ranks.
  for (std::size_t c = 0; c < (std::size_t(1) << D) && c < n; ++c)
    for (int a = 0; a < D; ++a)
      x[c][a] = (c >> a) & 1 ? upper - static_cast<Real>(1e-6) * (upper - lower) : lower + static_cast<Real>(1e-6) * (upper - lower);
  return x;
}

// Uneven contiguous slices: rank r starts with [begin(r), begin(r + 1)).
inline std::size_t slice_begin(std::size_t n, int rank, int size) {
  // Weights 1, 2, 3, ...: deliberately unbalanced.
  const std::size_t total = std::size_t(size) * (size + 1) / 2;
  const std::size_t before = std::size_t(rank) * (rank + 1) / 2;
  return n * before / total;
}

inline double mass_of(std::uint64_t id) { return 1.0 + 0.001 * static_cast<double>(id % 977); }

}  // namespace unisph::comm_test
