#pragma once
// Distance and inside/outside queries on a triangle mesh, usable in kernels on every policy:
// the views of a TriangleMeshSearch (triangle_mesh_search.hpp) in one memory space.
//
//   nearest(p)               exact closest point, the nearest triangle (its index in the mesh)
//                            and the feature it lies on; ties between triangles at equal
//                            distance go to the smaller triangle index
//   signed_distance(p)       distance, negative inside, signed by the angle-weighted
//                            pseudonormal of that feature (Bærentzen & Aanæs 2005): exact for
//                            closed, outward-oriented meshes
//   winding_number(p)        generalized winding number, hierarchical (Barill et al. 2018,
//                            dipole terms for far clusters): ~1 inside, ~0 outside, in between
//                            near holes of open meshes
//   exact_winding_number(p)  the same summed over every triangle (slow; the reference)

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

// A triangle's corners in BVH order (what the distance loop reads).
struct TriangleCorners {
  Vec<Real, 3> corner[3];
};
// What the sign needs of a triangle: unit face normal, edge pseudonormals (edge k from corner
// k to k + 1), vertex pseudonormals (angle weighted), and the triangle's index in the mesh.
struct TrianglePseudonormals {
  Vec<Real, 3> face;
  Vec<Real, 3> edge[3];
  Vec<Real, 3> vertex[3];
};
// Far-field data of a BVH node for the winding number: area-weighted normal sum, its centre and
// the radius of a ball around the centre that holds every triangle of the node.
struct WindingCluster {
  Vec<Real, 3> centre;
  Vec<Real, 3> area_normal;
  Real radius;
};
static_assert(std::is_trivially_copyable_v<TriangleCorners> && std::is_trivially_copyable_v<TrianglePseudonormals> &&
                  std::is_trivially_copyable_v<WindingCluster>,
              "mesh search data is copied to the device byte for byte: it must stay plain data.");

struct NearestTriangle {
  Vec<Real, 3> point;          // closest point on the mesh
  Real squared_distance;
  std::uint32_t triangle;      // index in TriangleMesh::triangles
  std::uint32_t bvh_position;  // where that triangle sits in the search's arrays
  Feature feature;
};

struct TriangleMeshSearchView {
  View<const BvhNode<3>> nodes;
  View<const TriangleCorners> corners;
  View<const TrianglePseudonormals> normals;
  View<const std::uint32_t> triangle_index;
  View<const WindingCluster> clusters;
  // A cluster is summed as one dipole where the point is farther than this times its radius.
  Real far_field_ratio;

  UNISPH_HOST_DEVICE NearestTriangle nearest(const Vec<Real, 3>& p) const {
    NearestTriangle best{p, std::numeric_limits<Real>::infinity(), UINT32_MAX, 0, Feature::face};
    std::uint32_t stack[bvh_max_depth + 2];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const std::uint32_t index = stack[--top];
      const BvhNode<3> node = nodes[index];
      if (box_squared_distance(p, node.lo, node.hi) > best.squared_distance) continue;
      if (node.is_leaf()) {
        for (std::uint32_t k = node.right_or_first; k < node.right_or_first + node.count; ++k) {
          const TriangleCorners t = corners[k];
          const ClosestPoint<Real, 3> c = closest_point_on_triangle(p, t.corner[0], t.corner[1], t.corner[2]);
          const Real d2 = squared_distance(p, c.point);
          if (d2 < best.squared_distance || (d2 == best.squared_distance && triangle_index[k] < best.triangle))
            best = {c.point, d2, triangle_index[k], k, c.feature};
        }
        continue;
      }
      const std::uint32_t left = index + 1, right = node.right_or_first;
      const Real d_left = box_squared_distance(p, nodes[left].lo, nodes[left].hi);
      const Real d_right = box_squared_distance(p, nodes[right].lo, nodes[right].hi);
      // Push the farther child first so that the nearer one is searched first and prunes more.
      const bool left_first = d_left <= d_right;
      const std::uint32_t near_child = left_first ? left : right, far_child = left_first ? right : left;
      const Real d_near = left_first ? d_left : d_right, d_far = left_first ? d_right : d_left;
      if (d_far <= best.squared_distance) stack[top++] = far_child;
      if (d_near <= best.squared_distance) stack[top++] = near_child;
    }
    return best;
  }

  // The pseudonormal of the feature the closest point lies on.
  UNISPH_HOST_DEVICE Vec<Real, 3> pseudonormal(const NearestTriangle& n) const {
    const TrianglePseudonormals& t = normals[n.bvh_position];
    if (is_edge(n.feature)) return t.edge[edge_of(n.feature)];
    if (is_vertex(n.feature)) return t.vertex[vertex_of(n.feature)];
    return t.face;
  }

  // +1 outside, -1 inside (by the pseudonormal); a point on the surface counts as outside.
  // Where the pseudonormal vanishes (two triangles folded back to back, 180 degrees apart: the
  // mesh stores a zero vector there) it decides nothing, and the winding number does.
  UNISPH_HOST_DEVICE int sign(const Vec<Real, 3>& p, const NearestTriangle& n) const {
    const Vec<Real, 3> normal = pseudonormal(n);
    if (normal == Vec<Real, 3>{}) return winding_number(p) > Real(0.5) ? -1 : 1;
    return dot(p - n.point, normal) >= Real(0) ? 1 : -1;
  }

  UNISPH_HOST_DEVICE Real signed_distance(const Vec<Real, 3>& p) const {
    const NearestTriangle n = nearest(p);
    const Real distance = std::sqrt(n.squared_distance);
    return sign(p, n) > 0 ? distance : -distance;
  }

  UNISPH_HOST_DEVICE Real winding_number(const Vec<Real, 3>& p) const {
    Real angle = Real(0);
    std::uint32_t stack[bvh_max_depth + 2];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const std::uint32_t index = stack[--top];
      const WindingCluster cluster = clusters[index];
      const Vec<Real, 3> r = cluster.centre - p;
      const Real distance2 = squared_norm(r);
      if (distance2 > far_field_ratio * far_field_ratio * cluster.radius * cluster.radius) {
        angle += dot(cluster.area_normal, r) / (distance2 * std::sqrt(distance2));  // dipole term
        continue;
      }
      const BvhNode<3> node = nodes[index];
      if (node.is_leaf()) {
        for (std::uint32_t k = node.right_or_first; k < node.right_or_first + node.count; ++k) {
          const TriangleCorners t = corners[k];
          angle += solid_angle(p, t.corner[0], t.corner[1], t.corner[2]);
        }
        continue;
      }
      stack[top++] = node.right_or_first;
      stack[top++] = index + 1;
    }
    return angle / (Real(4) * pi<Real>());
  }

  UNISPH_HOST_DEVICE Real exact_winding_number(const Vec<Real, 3>& p) const {
    Real angle = Real(0);
    for (Index k = 0; k < corners.size(); ++k) angle += solid_angle(p, corners[k].corner[0], corners[k].corner[1], corners[k].corner[2]);
    return angle / (Real(4) * pi<Real>());
  }
};
static_assert(std::is_trivially_copyable_v<TriangleMeshSearchView>,
              "TriangleMeshSearchView is captured by value into kernels, so it must be trivially copyable.");

}  // namespace unisph
