// Building the search structure of a triangle mesh (host only; the variables carry it to the device).
#include "unisph/geometry/triangle_mesh_search.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "unisph/geometry/mesh_repair.hpp"

namespace unisph {

namespace {

using Vec3 = Vec<double, 3>;

Vec3 normalised(const Vec3& v) {
  const double length = norm(v);
  return length > 0.0 ? v / length : v;
}
// A pseudonormal summed from unit normals of total weight `weight`; where they (nearly) cancel,
// as on a fold of two triangles back to back, its direction is noise: zero tells the query so.
Vec3 pseudonormal_or_zero(const Vec3& sum, double weight) {
  const double length = norm(sum);
  return length > 1e-9 * weight ? sum / length : Vec3{};
}
Vec<Real, 3> to_real(const Vec3& v) { return {{Real(v[0]), Real(v[1]), Real(v[2])}}; }

// Angle between u and v, accurate also near 0 and π.
double angle_between(const Vec3& u, const Vec3& v) { return std::atan2(norm(cross(u, v)), dot(u, v)); }

}  // namespace

TriangleMeshSearch::TriangleMeshSearch(const TriangleMesh& mesh, int leaf_size, Real far_field_ratio)
    : far_field_ratio_(far_field_ratio) {
  require_triangles(mesh, "a triangle mesh search (closest point, sign, winding number)");
  const std::size_t n = mesh.triangles.size();
  const auto& v = mesh.vertices;

  // Face normals (area-weighted and unit), vertex pseudonormals weighted by the corner angles,
  // edge pseudonormals as the sum of the unit normals of the triangles sharing the edge.
  std::vector<Vec3> area_normal(n), unit_normal(n);
  std::vector<Vec3> vertex_normal(v.size(), Vec3{});
  std::vector<double> vertex_weight(v.size(), 0.0);
  std::unordered_map<std::uint64_t, Vec3> edge_normal;
  std::unordered_map<std::uint64_t, double> edge_weight;
  edge_normal.reserve(3 * n);
  auto edge_key = [](std::uint32_t a, std::uint32_t b) {
    return (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
  };
  for (std::size_t t = 0; t < n; ++t) {
    const auto& tri = mesh.triangles[t];
    area_normal[t] = cross(v[tri[1]] - v[tri[0]], v[tri[2]] - v[tri[0]]) * 0.5;
    unit_normal[t] = normalised(area_normal[t]);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t here = tri[k], next = tri[(k + 1) % 3], previous = tri[(k + 2) % 3];
      const double angle = angle_between(v[next] - v[here], v[previous] - v[here]);
      vertex_normal[here] += angle * unit_normal[t];
      vertex_weight[here] += angle;
      edge_normal[edge_key(here, next)] += unit_normal[t];
      edge_weight[edge_key(here, next)] += 1.0;
    }
  }

  std::vector<Vec3> lo(n), hi(n);
  for (std::size_t t = 0; t < n; ++t) {
    const auto& tri = mesh.triangles[t];
    lo[t] = min(min(v[tri[0]], v[tri[1]]), v[tri[2]]);
    hi[t] = max(max(v[tri[0]], v[tri[1]]), v[tri[2]]);
  }
  const BvhLayout<3> layout = build_bvh<3>(lo, hi, leaf_size);

  std::vector<TriangleCorners> corners(n);
  std::vector<TrianglePseudonormals> normals(n);
  std::vector<std::uint32_t> index(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t t = layout.order[k];
    const auto& tri = mesh.triangles[t];
    index[k] = t;
    for (int c = 0; c < 3; ++c) {
      corners[k].corner[c] = to_real(v[tri[c]]);
      normals[k].vertex[c] = to_real(pseudonormal_or_zero(vertex_normal[tri[c]], vertex_weight[tri[c]]));
      const std::uint64_t edge = edge_key(tri[c], tri[(c + 1) % 3]);
      normals[k].edge[c] = to_real(pseudonormal_or_zero(edge_normal[edge], edge_weight[edge]));
    }
    normals[k].face = to_real(unit_normal[t]);
  }

  // Winding clusters per node: sums over the node's triangles (the nodes' ranges are contiguous).
  std::vector<WindingCluster> clusters(layout.nodes.size());
  for (std::size_t i = 0; i < layout.nodes.size(); ++i) {
    // A node covers the primitives from its leftmost leaf's first to its rightmost leaf's last.
    std::size_t first = i, last = i;
    while (!layout.nodes[first].is_leaf()) first = first + 1;
    while (!layout.nodes[last].is_leaf()) last = layout.nodes[last].right_or_first;
    const std::size_t begin = layout.nodes[first].right_or_first;
    const std::size_t end = layout.nodes[last].right_or_first + layout.nodes[last].count;
    Vec3 normal_sum{}, weighted_centre{};
    double area_sum = 0.0;
    for (std::size_t k = begin; k < end; ++k) {
      const std::uint32_t t = layout.order[k];
      const auto& tri = mesh.triangles[t];
      const double area = norm(area_normal[t]);
      normal_sum += area_normal[t];
      weighted_centre += area * (v[tri[0]] + v[tri[1]] + v[tri[2]]) / 3.0;
      area_sum += area;
    }
    Vec3 centre = area_sum > 0.0 ? weighted_centre / area_sum : v[mesh.triangles[layout.order[begin]][0]];
    double radius = 0.0;
    for (std::size_t k = begin; k < end; ++k)
      for (std::uint32_t corner : mesh.triangles[layout.order[k]]) radius = std::max(radius, norm(v[corner] - centre));
    clusters[i] = {to_real(centre), to_real(normal_sum), round_up(radius)};
  }

  nodes_.assign(layout.nodes);
  corners_.assign(corners);
  normals_.assign(normals);
  triangle_index_.assign(index);
  clusters_.assign(clusters);
}

}  // namespace unisph
