#pragma once
// A bounding-volume hierarchy over primitives given by their boxes, built on the host and
// flattened into one node array (depth first: an inner node's left child follows it, its
// right child is at `right_or_first`), so that it travels to the device as one variable and
// is walked there with a small fixed stack.

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <type_traits>
#include <vector>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"

namespace unisph {

template <int D>
struct BvhNode {
  Vec<Real, D> lo, hi;          // box of everything below, rounded outward to Real
  std::uint32_t right_or_first;  // inner: index of the right child; leaf: first primitive (in BVH order)
  std::uint32_t count;           // leaf: number of primitives (> 0); inner: 0

  UNISPH_HOST_DEVICE bool is_leaf() const { return count != 0; }
};
static_assert(std::is_trivially_copyable_v<BvhNode<3>> && std::is_trivially_default_constructible_v<BvhNode<3>>,
              "BVH nodes are copied to the device byte for byte: they must stay plain data.");

// Deepest path the builder makes; the query stacks are sized from it.
inline constexpr int bvh_max_depth = 48;

template <int D>
struct BvhLayout {
  std::vector<BvhNode<D>> nodes;
  std::vector<std::uint32_t> order;  // order[k]: input index of the k-th primitive in BVH order
};

// Builds the hierarchy top down by the surface area heuristic (16 bins of centroids per axis;
// the median along the longest axis where centroids coincide), down to `leaf_size` primitives
// per leaf. A branch that reaches bvh_max_depth ends in one larger leaf.
template <int D>
BvhLayout<D> build_bvh(std::span<const Vec<double, D>> primitive_lo, std::span<const Vec<double, D>> primitive_hi,
                       int leaf_size = 4);

// Squared distance from p to the box [lo, hi] (zero inside).
template <class T, int D>
UNISPH_HOST_DEVICE T box_squared_distance(const Vec<T, D>& p, const Vec<T, D>& lo, const Vec<T, D>& hi) {
  T d2 = T(0);
  for (int k = 0; k < D; ++k) {
    const T below = lo[k] - p[k], above = p[k] - hi[k];
    const T d = below > T(0) ? below : (above > T(0) ? above : T(0));
    d2 += d * d;
  }
  return d2;
}

// A double rounded to Real downward / upward, so that boxes stored in float still contain what they bound.
inline Real round_down(double x) {
  Real r = static_cast<Real>(x);
  if (static_cast<double>(r) > x) r = std::nextafter(r, -std::numeric_limits<Real>::infinity());
  return r;
}
inline Real round_up(double x) {
  Real r = static_cast<Real>(x);
  if (static_cast<double>(r) < x) r = std::nextafter(r, std::numeric_limits<Real>::infinity());
  return r;
}

}  // namespace unisph
