#pragma once
// Exact closest points on a triangle (3D) and a segment (2D), with the feature of the primitive
// the closest point lies on: the interior, an edge or a corner. The feature picks the
// pseudonormal that gives the sign of the distance (Bærentzen & Aanæs 2005).
//
// Host and device. The region tests follow the Voronoi regions of the triangle's features
// (Ericson, Real-Time Collision Detection, 5.1.5) and use only the signs of dot products, so a
// point is always given one feature, also on degenerate (zero-area) triangles.
//
// Same roundings on every policy: nvcc fuses a * b + c into one fused multiply-add by default,
// the host compiler (x86-64, ISO C++) does not; in the differences of products here that alone
// moves a distance by ten units in the last place. So every product below goes through
// exact_product, which the device compiler may not fuse, and seq, par and the GPU compute the
// same numbers (bit for bit on the host; the GPU's sqrt and division are also correctly rounded).

#include <cstdint>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"

namespace unisph {

namespace detail {
// a * b rounded on its own, never fused with an addition.
template <class T>
UNISPH_HOST_DEVICE inline T exact_product(T a, T b) {
#if UNISPH_DEVICE_CODE
  if constexpr (sizeof(T) == 8)
    return __dmul_rn(a, b);
  else
    return __fmul_rn(a, b);
#else
  return a * b;
#endif
}
template <class T, int D>
UNISPH_HOST_DEVICE inline T unfused_dot(const Vec<T, D>& a, const Vec<T, D>& b) {
  T sum = exact_product(a[0], b[0]);
  for (int k = 1; k < D; ++k) sum = sum + exact_product(a[k], b[k]);
  return sum;
}
template <class T, int D>
UNISPH_HOST_DEVICE inline Vec<T, D> unfused_scale(T s, const Vec<T, D>& a) {
  Vec<T, D> r;
  for (int k = 0; k < D; ++k) r[k] = exact_product(s, a[k]);
  return r;
}
}  // namespace detail

// |a - b|^2 with the same roundings on every policy.
template <class T, int D>
UNISPH_HOST_DEVICE inline T squared_distance(const Vec<T, D>& a, const Vec<T, D>& b) {
  const Vec<T, D> d = a - b;
  return detail::unfused_dot(d, d);
}

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
  T best_d2 = squared_distance(p, a);
  for (int k = 0; k < 3; ++k) {
    const Vec<T, 3> s = corners[k], e = corners[(k + 1) % 3];
    const Vec<T, 3> se = e - s;
    const T length2 = detail::unfused_dot(se, se);
    const T t = length2 > T(0) ? detail::unfused_dot(p - s, se) / length2 : T(0);
    ClosestPoint<T, 3> candidate;
    if (t <= T(0))
      candidate = {s, Feature(int(Feature::vertex0) + k)};
    else if (t >= T(1))
      candidate = {e, Feature(int(Feature::vertex0) + (k + 1) % 3)};
    else
      candidate = {s + detail::unfused_scale(t, se), Feature(int(Feature::edge0) + k)};
    const T d2 = squared_distance(p, candidate.point);
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
  const T d1 = detail::unfused_dot(ab, ap), d2 = detail::unfused_dot(ac, ap);
  if (d1 <= T(0) && d2 <= T(0)) return {a, Feature::vertex0};

  const Vec<T, 3> bp = p - b;
  const T d3 = detail::unfused_dot(ab, bp), d4 = detail::unfused_dot(ac, bp);
  if (d3 >= T(0) && d4 <= d3) return {b, Feature::vertex1};

  const T vc = detail::exact_product(d1, d4) - detail::exact_product(d3, d2);
  if (vc <= T(0) && d1 >= T(0) && d3 <= T(0)) {
    const T v = d1 / (d1 - d3);
    return {a + detail::unfused_scale(v, ab), Feature::edge0};
  }

  const Vec<T, 3> cp = p - c;
  const T d5 = detail::unfused_dot(ab, cp), d6 = detail::unfused_dot(ac, cp);
  if (d6 >= T(0) && d5 <= d6) return {c, Feature::vertex2};

  const T vb = detail::exact_product(d5, d2) - detail::exact_product(d1, d6);
  if (vb <= T(0) && d2 >= T(0) && d6 <= T(0)) {
    const T w = d2 / (d2 - d6);
    return {a + detail::unfused_scale(w, ac), Feature::edge2};
  }

  const T va = detail::exact_product(d3, d6) - detail::exact_product(d5, d4);
  if (va <= T(0) && (d4 - d3) >= T(0) && (d5 - d6) >= T(0)) {
    const T w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + detail::unfused_scale(w, c - b), Feature::edge1};
  }

  const T sum = va + vb + vc;
  if (!(sum > T(0))) {
    // Only a zero-area triangle gets here (all three region determinants vanish): fall back to the
    // nearest of its edges, which is exact for a segment-like triangle.
    return closest_point_on_triangle_edges(p, a, b, c);
  }
  const T denom = T(1) / sum;
  const T v = detail::exact_product(vb, denom), w = detail::exact_product(vc, denom);
  return {a + detail::unfused_scale(v, ab) + detail::unfused_scale(w, ac), Feature::face};
}

// Closest point of segment (a, b) to p, in any dimension: vertex0 = a, vertex1 = b, edge0 inside.
template <class T, int D>
UNISPH_HOST_DEVICE ClosestPoint<T, D> closest_point_on_segment(const Vec<T, D>& p, const Vec<T, D>& a,
                                                               const Vec<T, D>& b) {
  const Vec<T, D> ab = b - a;
  const T t = detail::unfused_dot(p - a, ab);
  if (t <= T(0)) return {a, Feature::vertex0};
  const T length2 = detail::unfused_dot(ab, ab);
  if (t >= length2) return {b, Feature::vertex1};
  return {a + detail::unfused_scale(t / length2, ab), Feature::edge0};
}

}  // namespace unisph
