// Building the search structure of a polygon set (host only).
#include "unisph/geometry/polygon_search.hpp"

#include "unisph/geometry/geometry_error.hpp"

namespace unisph {

namespace {
using Vec2 = Vec<double, 2>;
Vec<Real, 2> to_real(const Vec2& v) { return {{Real(v[0]), Real(v[1])}}; }
// Outward normal of an edge running a -> b of a counter-clockwise outer loop: to its right.
Vec2 outward_normal(const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double length = norm(d);
  return Vec2{{d[1], -d[0]}} / length;
}
Vec2 pseudonormal_or_zero(const Vec2& sum) {
  const double length = norm(sum);
  return length > 1e-9 ? sum / length : Vec2{};
}
}  // namespace

PolygonSearch::PolygonSearch(const PolygonSet& polygons, int leaf_size) {
  if (polygons.empty())
    throw GeometryError(polygons.source + ": the polygon set has no edges; a polygon search needs at least one loop");
  const std::size_t n = polygons.edges();
  std::vector<std::uint32_t> next(n), previous(n);
  for (std::size_t l = 0; l < polygons.loops(); ++l) {
    const std::uint32_t begin = polygons.loop_start[l], end = polygons.loop_start[l + 1];
    for (std::uint32_t i = begin; i < end; ++i) {
      next[i] = i + 1 == end ? begin : i + 1;
      previous[i] = i == begin ? end - 1 : i - 1;
    }
  }
  const auto& v = polygons.vertices;
  std::vector<Vec2> edge_normal(n), lo(n), hi(n);
  for (std::size_t i = 0; i < n; ++i) {
    edge_normal[i] = outward_normal(v[i], v[next[i]]);
    lo[i] = min(v[i], v[next[i]]);
    hi[i] = max(v[i], v[next[i]]);
  }
  const BvhLayout<2> layout = build_bvh<2>(lo, hi, leaf_size);
  std::vector<SegmentCorners> segments(n);
  std::vector<SegmentPseudonormals> normals(n);
  std::vector<std::uint32_t> index(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = layout.order[k];
    index[k] = i;
    segments[k] = {{to_real(v[i]), to_real(v[next[i]])}};
    // The two edges at a vertex meet with equal angle weights (π each) in 2D.
    normals[k] = {to_real(edge_normal[i]),
                  {to_real(pseudonormal_or_zero(edge_normal[previous[i]] + edge_normal[i])),
                   to_real(pseudonormal_or_zero(edge_normal[i] + edge_normal[next[i]]))}};
  }
  nodes_.assign(layout.nodes);
  segments_.assign(segments);
  normals_.assign(normals);
  edge_index_.assign(index);
}

}  // namespace unisph
