#pragma once
// Exact closest points on a triangle (3D) and a segment (2D), with the feature of the primitive
// the closest point lies on: the interior, an edge or a corner. The feature picks the
// pseudonormal that gives the sign of the distance (Bærentzen & Aanæs 2005).
//
// Host and device. The region tests follow the Voronoi regions of the triangle's features
// (Ericson, Real-Time Collision Detection, 5.1.5) and use only the signs of dot products, so a
// point is always given one feature, also on degenerate (zero-area) triangles.

#include <cstdint>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"

namespace unisph {

// Where on a triangle (or segment) the closest point lies.
//   face:      the interior (triangles only)
//   edge0..2:  edge k runs from corner k to corner (k + 1) % 3 (segments: edge0 is the segment)
//   vertex0..2: corner k
enum class Feature : std::uint8_t { face = 0, edge0 = 1, edge1 = 2, edge2 = 3, vertex0 = 4, vertex1 = 5, vertex2 = 6 };

UNISPH_HOST_DEVICE constexpr bool is_edge(Feature f) { return f >= Feature::edge0 && f <= Feature::edge2; }
UNISPH_HOST_DEVICE constexpr bool is_vertex(Feature f) { return f >= Feature::vertex0; }
UNISPH_HOST_DEVICE constexpr int edge_of(Feature f) { return int(f) - int(Feature::edge0); }
UNISPH_HOST_DEVICE constexpr int vertex_of(Feature f) { return int(f) - int(Feature::vertex0); }

template <class T, int D>
struct ClosestPoint {
  Vec<T, D> point;
  Feature feature;
};

// The nearest point on the three edges of (a, b, c): used for degenerate triangles.
template <class T>
UNISPH_HOST_DEVICE ClosestPoint<T, 3> closest_point_on_triangle_edges(const Vec<T, 3>& p, const Vec<T, 3>& a,
                                                                      const Vec<T, 3>& b, const Vec<T, 3>& c) {
  const Vec<T, 3> corners[3] = {a, b, c};
  ClosestPoint<T, 3> best{a, Feature::vertex0};
  T best_d2 = squared_norm(p - a);
  for (int k = 0; k < 3; ++k) {
    const Vec<T, 3> s = corners[k], e = corners[(k + 1) % 3];
    const Vec<T, 3> se = e - s;
    const T length2 = squared_norm(se);
    const T t = length2 > T(0) ? dot(p - s, se) / length2 : T(0);
    ClosestPoint<T, 3> candidate;
    if (t <= T(0))
      candidate = {s, Feature(int(Feature::vertex0) + k)};
    else if (t >= T(1))
      candidate = {e, Feature(int(Feature::vertex0) + (k + 1) % 3)};
    else
      candidate = {s + t * se, Feature(int(Feature::edge0) + k)};
    const T d2 = squared_norm(p - candidate.point);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = candidate;
    }
  }
  return best;
}

// Closest point of triangle (a, b, c) to p.
template <class T>
UNISPH_HOST_DEVICE ClosestPoint<T, 3> closest_point_on_triangle(const Vec<T, 3>& p, const Vec<T, 3>& a,
                                                                const Vec<T, 3>& b, const Vec<T, 3>& c) {
  const Vec<T, 3> ab = b - a, ac = c - a, ap = p - a;
  const T d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= T(0) && d2 <= T(0)) return {a, Feature::vertex0};

  const Vec<T, 3> bp = p - b;
  const T d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= T(0) && d4 <= d3) return {b, Feature::vertex1};

  const T vc = d1 * d4 - d3 * d2;
  if (vc <= T(0) && d1 >= T(0) && d3 <= T(0)) {
    const T v = d1 / (d1 - d3);
    return {a + v * ab, Feature::edge0};
  }

  const Vec<T, 3> cp = p - c;
  const T d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= T(0) && d5 <= d6) return {c, Feature::vertex2};

  const T vb = d5 * d2 - d1 * d6;
  if (vb <= T(0) && d2 >= T(0) && d6 <= T(0)) {
    const T w = d2 / (d2 - d6);
    return {a + w * ac, Feature::edge2};
  }

  const T va = d3 * d6 - d5 * d4;
  if (va <= T(0) && (d4 - d3) >= T(0) && (d5 - d6) >= T(0)) {
    const T w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), Feature::edge1};
  }

  const T sum = va + vb + vc;
  if (!(sum > T(0))) {
    // Only a zero-area triangle gets here (all three region determinants vanish): fall back to the
    // nearest of its edges, which is exact for a segment-like triangle.
    return closest_point_on_triangle_edges(p, a, b, c);
  }
  const T denom = T(1) / sum;
  const T v = vb * denom, w = vc * denom;
  return {a + ab * v + ac * w, Feature::face};
}

// Closest point of segment (a, b) to p, in any dimension: vertex0 = a, vertex1 = b, edge0 inside.
template <class T, int D>
UNISPH_HOST_DEVICE ClosestPoint<T, D> closest_point_on_segment(const Vec<T, D>& p, const Vec<T, D>& a,
                                                               const Vec<T, D>& b) {
  const Vec<T, D> ab = b - a;
  const T t = dot(p - a, ab);
  if (t <= T(0)) return {a, Feature::vertex0};
  const T length2 = squared_norm(ab);
  if (t >= length2) return {b, Feature::vertex1};
  return {a + (t / length2) * ab, Feature::edge0};
}

}  // namespace unisph
