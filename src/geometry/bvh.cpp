// BVH construction (host only).
#include "unisph/geometry/bvh.hpp"

#include <algorithm>
#include <numeric>

#include "unisph/geometry/geometry_error.hpp"

namespace unisph {

namespace {

template <int D>
class BvhBuilder {
 public:
  BvhBuilder(std::span<const Vec<double, D>> lo, std::span<const Vec<double, D>> hi, int leaf_size)
      : lo_(lo), hi_(hi), leaf_size_(std::max(1, leaf_size)) {
    centroid_.resize(lo.size());
    for (std::size_t i = 0; i < lo.size(); ++i) centroid_[i] = (lo[i] + hi[i]) * 0.5;
    layout_.order.resize(lo.size());
    std::iota(layout_.order.begin(), layout_.order.end(), std::uint32_t(0));
  }

  BvhLayout<D> build() {
    if (!lo_.empty()) build_node(0, lo_.size(), 0);
    return std::move(layout_);
  }

 private:
  std::uint32_t build_node(std::size_t begin, std::size_t end, int depth) {
    const std::uint32_t index = std::uint32_t(layout_.nodes.size());
    layout_.nodes.emplace_back();
    Vec<double, D> lo = lo_[layout_.order[begin]], hi = hi_[layout_.order[begin]];
    Vec<double, D> centre_lo = centroid_[layout_.order[begin]], centre_hi = centre_lo;
    for (std::size_t k = begin; k < end; ++k) {
      const std::uint32_t p = layout_.order[k];
      lo = min(lo, lo_[p]);
      hi = max(hi, hi_[p]);
      centre_lo = min(centre_lo, centroid_[p]);
      centre_hi = max(centre_hi, centroid_[p]);
    }
    BvhNode<D> node{};
    for (int k = 0; k < D; ++k) {
      node.lo[k] = round_down(lo[k]);
      node.hi[k] = round_up(hi[k]);
    }
    const std::size_t count = end - begin;
    if (count <= std::size_t(leaf_size_) || depth + 1 >= bvh_max_depth) {
      node.right_or_first = std::uint32_t(begin);
      node.count = std::uint32_t(count);
      layout_.nodes[index] = node;
      return index;
    }
    int axis = 0;
    for (int k = 1; k < D; ++k)
      if (centre_hi[k] - centre_lo[k] > centre_hi[axis] - centre_lo[axis]) axis = k;
    const std::size_t middle = begin + count / 2;
    std::nth_element(layout_.order.begin() + begin, layout_.order.begin() + middle, layout_.order.begin() + end,
                     [&](std::uint32_t a, std::uint32_t b) {
                       return centroid_[a][axis] != centroid_[b][axis] ? centroid_[a][axis] < centroid_[b][axis] : a < b;
                     });
    build_node(begin, middle, depth + 1);  // lands at index + 1
    node.right_or_first = build_node(middle, end, depth + 1);
    node.count = 0;
    layout_.nodes[index] = node;
    return index;
  }

  std::span<const Vec<double, D>> lo_, hi_;
  std::vector<Vec<double, D>> centroid_;
  int leaf_size_;
  BvhLayout<D> layout_;
};

}  // namespace

template <int D>
BvhLayout<D> build_bvh(std::span<const Vec<double, D>> primitive_lo, std::span<const Vec<double, D>> primitive_hi,
                       int leaf_size) {
  if (primitive_lo.size() != primitive_hi.size())
    throw Error("build_bvh: " + std::to_string(primitive_lo.size()) + " lower corners but " +
                std::to_string(primitive_hi.size()) + " upper corners");
  if (primitive_lo.size() >= UINT32_MAX) throw Error("build_bvh: more than 2^32 - 1 primitives");
  return BvhBuilder<D>(primitive_lo, primitive_hi, leaf_size).build();
}

template BvhLayout<2> build_bvh<2>(std::span<const Vec<double, 2>>, std::span<const Vec<double, 2>>, int);
template BvhLayout<3> build_bvh<3>(std::span<const Vec<double, 3>>, std::span<const Vec<double, 3>>, int);

}  // namespace unisph
