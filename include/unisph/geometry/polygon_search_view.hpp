#pragma once
// Distance and inside/outside queries on closed polygons in the plane, usable in kernels on
// every policy: the views of a PolygonSearch (polygon_search.hpp) in one memory space. The 2D
// counterpart of TriangleMeshSearchView:
//   nearest(p)          exact closest point, nearest edge (its index in PolygonSet order; ties
//                       go to the smaller index) and whether it is the edge's interior or an end
//   signed_distance(p)  negative inside, signed by the edge normal or the vertex pseudonormal
//                       (the normalised sum of the two edges' normals)
//   winding_number(p)   sum of the angles the edges subtend / 2π, over every edge (exact)

#include <cstdint>
#include <limits>
#include <type_traits>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/geometry/bvh.hpp"
#include "unisph/geometry/closest_point.hpp"
#include "unisph/geometry/winding_number.hpp"
#include "unisph/memory/view.hpp"

namespace unisph {

struct SegmentCorners {
  Vec<Real, 2> corner[2];
};
// Outward unit normal of the edge and the pseudonormals of its two ends (zero where the two
// edges at a vertex fold back onto each other: the winding number decides there).
struct SegmentPseudonormals {
  Vec<Real, 2> edge;
  Vec<Real, 2> vertex[2];
};
static_assert(std::is_trivially_copyable_v<SegmentCorners> && std::is_trivially_copyable_v<SegmentPseudonormals>,
              "polygon search data is copied to the device byte for byte: it must stay plain data.");

struct NearestEdge {
  Vec<Real, 2> point;
  Real squared_distance;
  std::uint32_t edge;          // index of the edge (= of its first vertex) in the PolygonSet
  std::uint32_t bvh_position;  // where it sits in the search's arrays
  Feature feature;             // edge0 (interior), vertex0 or vertex1
};

struct PolygonSearchView {
  View<const BvhNode<2>> nodes;
  View<const SegmentCorners> segments;
  View<const SegmentPseudonormals> normals;
  View<const std::uint32_t> edge_index;

  UNISPH_HOST_DEVICE NearestEdge nearest(const Vec<Real, 2>& p) const {
    NearestEdge best{p, std::numeric_limits<Real>::infinity(), UINT32_MAX, 0, Feature::edge0};
    std::uint32_t stack[bvh_max_depth + 2];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const std::uint32_t index = stack[--top];
      const BvhNode<2> node = nodes[index];
      if (box_squared_distance(p, node.lo, node.hi) > best.squared_distance) continue;
      if (node.is_leaf()) {
        for (std::uint32_t k = node.right_or_first; k < node.right_or_first + node.count; ++k) {
          const SegmentCorners s = segments[k];
          const ClosestPoint<Real, 2> c = closest_point_on_segment(p, s.corner[0], s.corner[1]);
          const Real d2 = squared_distance(p, c.point);
          if (d2 < best.squared_distance || (d2 == best.squared_distance && edge_index[k] < best.edge))
            best = {c.point, d2, edge_index[k], k, c.feature};
        }
        continue;
      }
      const std::uint32_t left = index + 1, right = node.right_or_first;
      const Real d_left = box_squared_distance(p, nodes[left].lo, nodes[left].hi);
      const Real d_right = box_squared_distance(p, nodes[right].lo, nodes[right].hi);
      const bool left_first = d_left <= d_right;
      const std::uint32_t near_child = left_first ? left : right, far_child = left_first ? right : left;
      const Real d_near = left_first ? d_left : d_right, d_far = left_first ? d_right : d_left;
      if (d_far <= best.squared_distance) stack[top++] = far_child;
      if (d_near <= best.squared_distance) stack[top++] = near_child;
    }
    return best;
  }

  UNISPH_HOST_DEVICE Vec<Real, 2> pseudonormal(const NearestEdge& n) const {
    const SegmentPseudonormals& s = normals[n.bvh_position];
    if (is_vertex(n.feature)) return s.vertex[vertex_of(n.feature)];
    return s.edge;
  }

  // +1 outside, -1 inside; a point on the boundary counts as outside.
  UNISPH_HOST_DEVICE int sign(const Vec<Real, 2>& p, const NearestEdge& n) const {
    const Vec<Real, 2> normal = pseudonormal(n);
    if (normal == Vec<Real, 2>{}) return winding_number(p) > Real(0.5) ? -1 : 1;
    return dot(p - n.point, normal) >= Real(0) ? 1 : -1;
  }

  UNISPH_HOST_DEVICE Real signed_distance(const Vec<Real, 2>& p) const {
    const NearestEdge n = nearest(p);
    const Real distance = std::sqrt(n.squared_distance);
    return sign(p, n) > 0 ? distance : -distance;
  }

  UNISPH_HOST_DEVICE Real winding_number(const Vec<Real, 2>& p) const {
    Real angle = Real(0);
    for (Index k = 0; k < segments.size(); ++k) angle += subtended_angle(p, segments[k].corner[0], segments[k].corner[1]);
    return angle / (Real(2) * pi<Real>());
  }
};
static_assert(std::is_trivially_copyable_v<PolygonSearchView>,
              "PolygonSearchView is captured by value into kernels, so it must be trivially copyable.");

}  // namespace unisph
