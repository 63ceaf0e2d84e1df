// BVH construction (host only).
#include "unisph/geometry/bvh.hpp"

#include <algorithm>
#include <limits>
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
    const std::size_t middle = split(begin, end, centre_lo, centre_hi);
    build_node(begin, middle, depth + 1);  // lands at index + 1
    node.right_or_first = build_node(middle, end, depth + 1);
    node.count = 0;
    layout_.nodes[index] = node;
    return index;
  }

  // Half the surface area of a box (its perimeter in 2D): the chance that a query ball near the
  // box reaches into it grows with it.
  static double area(const Vec<double, D>& lo, const Vec<double, D>& hi) {
    const Vec<double, D> e = hi - lo;
    if constexpr (D == 3)
      return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
    else
      return e[0] + e[1];
  }

  // Splits [begin, end) by the surface area heuristic over 16 bins of centroids per axis;
  // falls back to the median along the longest axis where the centroids coincide.
  std::size_t split(std::size_t begin, std::size_t end, const Vec<double, D>& centre_lo,
                    const Vec<double, D>& centre_hi) {
    constexpr int bins = 16;
    double best_cost = std::numeric_limits<double>::infinity();
    int best_axis = -1, best_bin = 0;
    for (int axis = 0; axis < D; ++axis) {
      const double extent = centre_hi[axis] - centre_lo[axis];
      if (!(extent > 0.0)) continue;
      Vec<double, D> bin_lo[bins], bin_hi[bins];
      std::size_t bin_count[bins] = {};
      for (std::size_t k = begin; k < end; ++k) {
        const std::uint32_t p = layout_.order[k];
        const int b = bin_of(centroid_[p][axis], centre_lo[axis], extent);
        bin_lo[b] = bin_count[b] ? min(bin_lo[b], lo_[p]) : lo_[p];
        bin_hi[b] = bin_count[b] ? max(bin_hi[b], hi_[p]) : hi_[p];
        ++bin_count[b];
      }
      // Cost of splitting after bin i: sweep from the right, then from the left.
      double right_cost[bins] = {};
      Vec<double, D> lo, hi;
      std::size_t count = 0;
      for (int i = bins - 1; i > 0; --i) {
        if (bin_count[i]) {
          lo = count ? min(lo, bin_lo[i]) : bin_lo[i];
          hi = count ? max(hi, bin_hi[i]) : bin_hi[i];
          count += bin_count[i];
        }
        right_cost[i - 1] = count ? area(lo, hi) * double(count) : 0.0;
      }
      count = 0;
      for (int i = 0; i < bins - 1; ++i) {
        if (bin_count[i]) {
          lo = count ? min(lo, bin_lo[i]) : bin_lo[i];
          hi = count ? max(hi, bin_hi[i]) : bin_hi[i];
          count += bin_count[i];
        }
        if (count == 0 || count == end - begin) continue;
        const double cost = area(lo, hi) * double(count) + right_cost[i];
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_bin = i;
        }
      }
    }
    if (best_axis >= 0) {
      const double extent = centre_hi[best_axis] - centre_lo[best_axis];
      const auto middle = std::partition(layout_.order.begin() + begin, layout_.order.begin() + end, [&](std::uint32_t p) {
        return bin_of(centroid_[p][best_axis], centre_lo[best_axis], extent) <= best_bin;
      });
      return std::size_t(middle - layout_.order.begin());
    }
    int axis = 0;
    for (int k = 1; k < D; ++k)
      if (centre_hi[k] - centre_lo[k] > centre_hi[axis] - centre_lo[axis]) axis = k;
    const std::size_t middle = begin + (end - begin) / 2;
    std::nth_element(layout_.order.begin() + begin, layout_.order.begin() + middle, layout_.order.begin() + end,
                     [&](std::uint32_t a, std::uint32_t b) {
                       return centroid_[a][axis] != centroid_[b][axis] ? centroid_[a][axis] < centroid_[b][axis] : a < b;
                     });
    return middle;
  }

  // Clamped before the conversion: with coordinates near the largest double, 16 (x - lo)
  // overflows to infinity (or x - lo does, giving NaN), and converting those to int is undefined
  // (found by the polygon fuzzer). Finite values get the bins they always had.
  static int bin_of(double x, double lo, double extent) {
    const double b = 16.0 * (x - lo) / extent;
    if (!(b > 0.0)) return 0;
    return b >= 15.0 ? 15 : int(b);
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
