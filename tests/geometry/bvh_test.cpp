// The flattened BVH: every primitive in exactly one leaf, boxes that contain what they bound,
// children laid out depth first, bounded depth.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "unisph/geometry/bvh.hpp"

namespace {
using namespace unisph;

template <int D>
int check_node(const BvhLayout<D>& bvh, std::uint32_t index, const std::vector<Vec<double, D>>& lo,
               const std::vector<Vec<double, D>>& hi, std::vector<int>& seen) {
  const BvhNode<D>& node = bvh.nodes[index];
  if (node.is_leaf()) {
    for (std::uint32_t k = node.right_or_first; k < node.right_or_first + node.count; ++k) {
      const std::uint32_t p = bvh.order[k];
      ++seen[p];
      for (int a = 0; a < D; ++a) {
        EXPECT_LE(node.lo[a], lo[p][a]);
        EXPECT_GE(node.hi[a], hi[p][a]);
      }
    }
    return 1;
  }
  for (std::uint32_t child : {index + 1, node.right_or_first}) {
    EXPECT_GT(child, index);
    for (int a = 0; a < D; ++a) {
      EXPECT_LE(node.lo[a], bvh.nodes[child].lo[a]);
      EXPECT_GE(node.hi[a], bvh.nodes[child].hi[a]);
    }
  }
  return 1 + std::max(check_node(bvh, index + 1, lo, hi, seen), check_node(bvh, node.right_or_first, lo, hi, seen));
}

TEST(HostBvh, EveryPrimitiveOnceInsideItsBoxes) {
  std::mt19937 random(1);
  std::uniform_real_distribution<double> unit(-10, 10);
  for (std::size_t n : {1u, 2u, 5u, 1000u, 65537u}) {
    std::vector<Vec<double, 3>> lo(n), hi(n);
    for (std::size_t i = 0; i < n; ++i) {
      lo[i] = {{unit(random), unit(random), unit(random)}};
      hi[i] = lo[i] + Vec<double, 3>{{0.1, 0.2, 0.3}};
    }
    const BvhLayout<3> bvh = build_bvh<3>(lo, hi, 4);
    std::vector<int> seen(n, 0);
    const int depth = check_node(bvh, 0, lo, hi, seen);
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(seen[i], 1) << "primitive " << i << " of " << n;
    EXPECT_LT(depth, bvh_max_depth);
    EXPECT_EQ(bvh.nodes.size() % 2, 1u) << "a binary tree with leaves at the bottom has an odd node count";
  }
}

TEST(HostBvh, IdenticalPrimitivesAndTwoDimensions) {
  std::vector<Vec<double, 2>> lo(100, Vec<double, 2>{{1, 1}}), hi(100, Vec<double, 2>{{2, 2}});
  const BvhLayout<2> bvh = build_bvh<2>(lo, hi, 4);
  std::vector<int> seen(100, 0);
  check_node(bvh, 0, lo, hi, seen);
  for (int s : seen) EXPECT_EQ(s, 1);
  EXPECT_TRUE(build_bvh<2>({}, {}, 4).nodes.empty());
}

// Boxes that reach the largest doubles (a polygon file with a vertex at y = 1.22e308, found by the
// polygon fuzzer): the binning must not overflow into an undefined conversion, and the tree stays whole.
TEST(HostBvh, CoordinatesNearTheLargestDouble) {
  const double big = 1.2222e308;
  std::vector<Vec<double, 2>> lo, hi;
  for (int i = 0; i < 40; ++i) {
    lo.push_back({{double(i), 0.0}});
    hi.push_back({{double(i) + 1, i % 3 == 0 ? big : 1.0}});
  }
  lo.push_back({{-big, -big}});
  hi.push_back({{big, big}});
  const BvhLayout<2> bvh = build_bvh<2>(lo, hi, 4);
  std::vector<int> seen(lo.size(), 0);
  const int depth = check_node(bvh, 0, lo, hi, seen);
  for (int s : seen) EXPECT_EQ(s, 1);
  EXPECT_LT(depth, bvh_max_depth);
}

}  // namespace
