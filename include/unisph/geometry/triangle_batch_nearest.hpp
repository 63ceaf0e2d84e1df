#pragma once
// The nearest triangle of every point of a small batch of nearby points (the 64 data points of a
// level-set package, the 8 child-cell centres of a coarse cell) with one BVH walk for the whole
// batch instead of one per point, and with the same answer as TriangleMeshSearchView::nearest at
// every point (the smallest squared distance, ties to the smaller triangle index, computed by the
// same closest_point_on_triangle on the same doubles).
//
//   1. Candidates. d_c = the distance from the batch's centre c to the mesh (one nearest query),
//      rho = the largest distance from c to a point of the batch, R = d_c + rho bounds every
//      point's distance to the mesh. A triangle that is nearest to some point p of the batch lies
//      within R of p, so within R of the batch's box and within R + rho of c: the candidates are
//      the triangles passing both tests (one BVH walk; a little slack on R for round-off), sorted
//      by their distance from c. At most batch_nearest_capacity are kept (the nearest to c).
//   2. Filter, in float. The points in groups of four (one SSE vector) against the candidates in
//      that order: a branchless squared point-triangle distance (the three clamped edge distances,
//      or the plane distance where the point projects inside) on structure-of-arrays data relative
//      to c. A group stops at the first candidate whose distance from c, less each point's
//      distance from c, exceeds the point's float minimum plus the margin (so do all later ones).
//      The float error is at most E (below), so the exact nearest triangle's float distance lies
//      within 2 E of the float minimum.
//   3. Exact. Only candidates within 2 E of the point's float minimum (about 1.1 to 1.3 per point
//      on teapot.stl) go through closest_point_on_triangle in Real (double), with the tie rule of
//      nearest(): the result is that of the per-point search bit for bit (the sign, pseudonormal
//      or winding number, is then computed from it as before). A point whose group went through a
//      list that was cut at the capacity, and whose minimum does not rule out the triangles that
//      were dropped, is searched on its own (search.nearest).
//
// The error bound E: every float quantity is a few roundings of numbers no larger than
// S = rho + the largest distance from c to a candidate's corner, so the float closest-point
// vector is off by at most delta = 64 eps_f S (generous: the chain of operations has fewer than
// ten roundings), and a squared distance d^2 <= R^2 by at most (2 R + delta) delta plus the
// roundings of the squares (16 eps_f R^2). Sliver triangles (sine of the angle at a corner below
// 1e-6), whose unit normal float cannot carry, are filtered by their edges only, which
// overestimates their distance by at most their width squared: that is subtracted before the
// comparison. In a single-precision build (Real = float) the exact stage's own error, relative
// to the coordinates' magnitude, is added to delta.
//
// Host and device code (no allocation; about 60 KB of stack for 64 points), launched on the
// host policies only: on the GPU one thread per point with its own BVH walk is the better layout
// (and the device keeps it). In CUDA translation units the filter is the plain scalar loop.

#include <cstdint>
#include <cstring>
#include <limits>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/geometry/bvh.hpp"
#include "unisph/geometry/closest_point.hpp"
#include "unisph/geometry/triangle_mesh_search_view.hpp"

namespace unisph {

// Candidates kept per batch (the nearest to the centre; points that may need a dropped one are
// searched on their own).
inline constexpr int batch_nearest_capacity = 128;

namespace detail {
// Squared distance between the boxes [alo, ahi] and [blo, bhi] (zero where they overlap).
template <class T>
UNISPH_HOST_DEVICE inline T box_box_squared_distance(const Vec<T, 3>& alo, const Vec<T, 3>& ahi, const Vec<T, 3>& blo,
                                                     const Vec<T, 3>& bhi) {
  T d2 = T(0);
  for (int k = 0; k < 3; ++k) {
    const T below = blo[k] - ahi[k], above = alo[k] - bhi[k];
    const T d = below > T(0) ? below : (above > T(0) ? above : T(0));
    d2 += d * d;
  }
  return d2;
}

// A triangle of the filter, relative to the batch's centre: corner a, b, c, edges e0 = b - a,
// e1 = c - b, e2 = a - c with 1 / |e|^2 (0 for a zero-length edge), the unit normal n with
// offset hn (plane distance = p.n + hn), the in-plane edge normals m_k = n x e_k with offsets
// (p projects inside where every p.m_k + h_k >= 0; m = 0, h = -1 for a sliver: never inside),
// and the slack subtracted before the comparison (a sliver's width squared).
struct BatchTriangles {
  float ax[batch_nearest_capacity], ay[batch_nearest_capacity], az[batch_nearest_capacity];
  float bx[batch_nearest_capacity], by[batch_nearest_capacity], bz[batch_nearest_capacity];
  float cx[batch_nearest_capacity], cy[batch_nearest_capacity], cz[batch_nearest_capacity];
  float e0x[batch_nearest_capacity], e0y[batch_nearest_capacity], e0z[batch_nearest_capacity];
  float e1x[batch_nearest_capacity], e1y[batch_nearest_capacity], e1z[batch_nearest_capacity];
  float e2x[batch_nearest_capacity], e2y[batch_nearest_capacity], e2z[batch_nearest_capacity];
  float i0[batch_nearest_capacity], i1[batch_nearest_capacity], i2[batch_nearest_capacity];
  float nx[batch_nearest_capacity], ny[batch_nearest_capacity], nz[batch_nearest_capacity], hn[batch_nearest_capacity];
  float m0x[batch_nearest_capacity], m0y[batch_nearest_capacity], m0z[batch_nearest_capacity], h0[batch_nearest_capacity];
  float m1x[batch_nearest_capacity], m1y[batch_nearest_capacity], m1z[batch_nearest_capacity], h1[batch_nearest_capacity];
  float m2x[batch_nearest_capacity], m2y[batch_nearest_capacity], m2z[batch_nearest_capacity], h2[batch_nearest_capacity];
  float slack[batch_nearest_capacity];
  float lower[batch_nearest_capacity];  // a lower bound of the distance from the centre (sorted ascending)
  std::uint32_t position[batch_nearest_capacity];  // in the search's (BVH) order
  int count;
};

UNISPH_HOST_DEVICE inline float inverse_or_zero(Real length2) { return length2 > Real(0) ? float(Real(1) / length2) : 0.0f; }

// Adds triangle `position` (corners relative to the centre: a, b, c) to the filter's arrays;
// returns the largest distance of a corner from the centre.
UNISPH_HOST_DEVICE inline Real add_batch_triangle(BatchTriangles& t, std::uint32_t position, const Vec<Real, 3>& a,
                                                  const Vec<Real, 3>& b, const Vec<Real, 3>& c) {
  const int j = t.count++;
  t.position[j] = position;
  t.ax[j] = float(a[0]), t.ay[j] = float(a[1]), t.az[j] = float(a[2]);
  t.bx[j] = float(b[0]), t.by[j] = float(b[1]), t.bz[j] = float(b[2]);
  t.cx[j] = float(c[0]), t.cy[j] = float(c[1]), t.cz[j] = float(c[2]);
  const Vec<Real, 3> e0 = b - a, e1 = c - b, e2 = a - c;
  t.e0x[j] = float(e0[0]), t.e0y[j] = float(e0[1]), t.e0z[j] = float(e0[2]);
  t.e1x[j] = float(e1[0]), t.e1y[j] = float(e1[1]), t.e1z[j] = float(e1[2]);
  t.e2x[j] = float(e2[0]), t.e2y[j] = float(e2[1]), t.e2z[j] = float(e2[2]);
  const Real l0 = squared_norm(e0), l1 = squared_norm(e1), l2 = squared_norm(e2);
  t.i0[j] = inverse_or_zero(l0), t.i1[j] = inverse_or_zero(l1), t.i2[j] = inverse_or_zero(l2);
  const Vec<Real, 3> n = cross(e0, -e2);
  const Real n2 = squared_norm(n);
  // Sine of the angle at corner a, squared, against 1e-12: a sliver.
  if (n2 > Real(1e-12) * l0 * l2 && n2 > Real(0)) {
    const Vec<Real, 3> u = n / std::sqrt(n2);
    const Vec<Real, 3> m0 = cross(u, e0), m1 = cross(u, e1), m2 = cross(u, e2);
    t.nx[j] = float(u[0]), t.ny[j] = float(u[1]), t.nz[j] = float(u[2]), t.hn[j] = float(-dot(u, a));
    t.m0x[j] = float(m0[0]), t.m0y[j] = float(m0[1]), t.m0z[j] = float(m0[2]), t.h0[j] = float(-dot(m0, a));
    t.m1x[j] = float(m1[0]), t.m1y[j] = float(m1[1]), t.m1z[j] = float(m1[2]), t.h1[j] = float(-dot(m1, b));
    t.m2x[j] = float(m2[0]), t.m2y[j] = float(m2[1]), t.m2z[j] = float(m2[2]), t.h2[j] = float(-dot(m2, c));
    t.slack[j] = 0.0f;
  } else {
    t.nx[j] = t.ny[j] = t.nz[j] = t.hn[j] = 0.0f;
    t.m0x[j] = t.m0y[j] = t.m0z[j] = 0.0f, t.h0[j] = -1.0f;
    t.m1x[j] = t.m1y[j] = t.m1z[j] = 0.0f, t.h1[j] = -1.0f;
    t.m2x[j] = t.m2y[j] = t.m2z[j] = 0.0f, t.h2[j] = -1.0f;
    // Width = twice the area over the longest edge; its square, doubled for the float roundings.
    const Real longest2 = l0 > l1 ? (l0 > l2 ? l0 : l2) : (l1 > l2 ? l1 : l2);
    t.slack[j] = longest2 > Real(0) ? float(Real(2) * n2 / longest2) * 1.001f : 0.0f;
  }
  Real far2 = squared_norm(a);
  far2 = squared_norm(b) > far2 ? squared_norm(b) : far2;
  far2 = squared_norm(c) > far2 ? squared_norm(c) : far2;
  return std::sqrt(far2);
}

// Lanes of the filter: on the host (GCC and Clang) four points at a time in the compilers'
// vector extension. GCC does not vectorise the plain loop over the points under the default
// -ftrapping-math (jump threading of the clamps leaves floating-point work under branches, which
// it may then not speculate), so the vector type is spelled out; elsewhere one lane.
struct BatchFilterScalar {
  template <class F>
  UNISPH_HOST_DEVICE static F lane_min(F a, F b) {
    return a < b ? a : b;
  }
  template <class F>
  UNISPH_HOST_DEVICE static F lane_max(F a, F b) {
    return a > b ? a : b;
  }
};
#if defined(__GNUC__) && !defined(__CUDA_ARCH__)
#define UNISPH_BATCH_FILTER_LANES 4
typedef float batch_filter_lanes __attribute__((vector_size(16)));
#else
#define UNISPH_BATCH_FILTER_LANES 1
typedef float batch_filter_lanes;
#endif

template <class Mask>
UNISPH_HOST_DEVICE inline bool all_lanes(const Mask& m) {
#if UNISPH_BATCH_FILTER_LANES == 4
  return m[0] && m[1] && m[2] && m[3];
#else
  return m;
#endif
}

// Float squared distances of the points (px, py, pz; r = their distance from the centre, rounded
// up) to the candidates, into rows[j * Points + i]; best[] keeps each point's minimum. The
// candidates come sorted by their lower bound t.lower (the distance from the centre, rounded
// down), so a group of `lanes` points stops at the first candidate j whose lower bound, less
// the point's r, exceeds the square root of best + margin at every point of the group: that
// candidate and all later ones are farther than the nearest by more than the margin.
// processed[g] = the candidates group g evaluated.
template <int Points>
UNISPH_HOST_DEVICE inline void batch_filter(const BatchTriangles& t, const float* __restrict__ px,
                                            const float* __restrict__ py, const float* __restrict__ pz,
                                            const float* __restrict__ r, float margin, float* __restrict__ rows,
                                            float* __restrict__ best, int* __restrict__ processed) {
  using F = batch_filter_lanes;
  constexpr int lanes = UNISPH_BATCH_FILTER_LANES, groups = Points / lanes;
  static_assert(Points % lanes == 0, "the batch's points fill whole vectors");
  using S = BatchFilterScalar;
  const F zero = F{} * 0.0f, one = zero + 1.0f, huge = zero + 3e38f;
  for (int g = 0; g < groups; ++g) processed[g] = t.count;
  int running = groups;
  for (int j = 0; j < t.count && running > 0; ++j) {
    const float ax = t.ax[j], ay = t.ay[j], az = t.az[j];
    const float bx = t.bx[j], by = t.by[j], bz = t.bz[j];
    const float cx = t.cx[j], cy = t.cy[j], cz = t.cz[j];
    const float e0x = t.e0x[j], e0y = t.e0y[j], e0z = t.e0z[j], i0 = t.i0[j];
    const float e1x = t.e1x[j], e1y = t.e1y[j], e1z = t.e1z[j], i1 = t.i1[j];
    const float e2x = t.e2x[j], e2y = t.e2y[j], e2z = t.e2z[j], i2 = t.i2[j];
    const float nx = t.nx[j], ny = t.ny[j], nz = t.nz[j], hn = t.hn[j];
    const float m0x = t.m0x[j], m0y = t.m0y[j], m0z = t.m0z[j], h0 = t.h0[j];
    const float m1x = t.m1x[j], m1y = t.m1y[j], m1z = t.m1z[j], h1 = t.h1[j];
    const float m2x = t.m2x[j], m2y = t.m2y[j], m2z = t.m2z[j], h2 = t.h2[j];
    const float lower = t.lower[j];
    for (int g = 0; g < groups; ++g) {
      if (processed[g] != t.count) continue;
      const int i = g * lanes;
      F x, y, z, b, rr;
      memcpy(&b, best + i, sizeof(F));
      memcpy(&rr, r + i, sizeof(F));
      const F a = lower - rr;
      if (all_lanes((a > zero) & (a * a > b + margin))) {
        processed[g] = j;
        --running;
        continue;
      }
      memcpy(&x, px + i, sizeof(F));
      memcpy(&y, py + i, sizeof(F));
      memcpy(&z, pz + i, sizeof(F));
      // Edge 0 from a.
      const F u0x = x - ax, u0y = y - ay, u0z = z - az;
      const F s0 = S::lane_min(S::lane_max((u0x * e0x + u0y * e0y + u0z * e0z) * i0, zero), one);
      const F w0x = u0x - s0 * e0x, w0y = u0y - s0 * e0y, w0z = u0z - s0 * e0z;
      const F d0 = w0x * w0x + w0y * w0y + w0z * w0z;
      // Edge 1 from b.
      const F u1x = x - bx, u1y = y - by, u1z = z - bz;
      const F s1 = S::lane_min(S::lane_max((u1x * e1x + u1y * e1y + u1z * e1z) * i1, zero), one);
      const F w1x = u1x - s1 * e1x, w1y = u1y - s1 * e1y, w1z = u1z - s1 * e1z;
      const F d1 = w1x * w1x + w1y * w1y + w1z * w1z;
      // Edge 2 from c.
      const F u2x = x - cx, u2y = y - cy, u2z = z - cz;
      const F s2 = S::lane_min(S::lane_max((u2x * e2x + u2y * e2y + u2z * e2z) * i2, zero), one);
      const F w2x = u2x - s2 * e2x, w2y = u2y - s2 * e2y, w2z = u2z - s2 * e2z;
      const F d2 = w2x * w2x + w2y * w2y + w2z * w2z;
      // The face where the point projects inside (every in-plane edge test >= 0), else the
      // nearest edge: a minimum with a penalty on the face (the plane distance never exceeds the
      // edges').
      const F g0 = x * m0x + y * m0y + z * m0z + h0;
      const F g1 = x * m1x + y * m1y + z * m1z + h1;
      const F g2 = x * m2x + y * m2y + z * m2z + h2;
      const F h = x * nx + y * ny + z * nz + hn;
      const F inside = S::lane_min(S::lane_min(g0, g1), g2);
      const F face = h * h + (inside >= zero ? zero : huge);
      const F d = S::lane_min(S::lane_min(S::lane_min(d0, d1), d2), face);
      b = S::lane_min(d, b);
      memcpy(rows + j * Points + i, &d, sizeof(F));
      memcpy(best + i, &b, sizeof(F));
    }
  }
}
}  // namespace detail

// nearest[i] = search.nearest(x[i]) for the `Points` points x, which should lie close together
// around `centre` (the answer is the same for any points; the work grows with their spread).
// centre_squared_distance: the centre's squared distance to the mesh, or any upper bound of it
// (the candidates then are more).
template <int Points>
UNISPH_HOST_DEVICE void batch_nearest(const TriangleMeshSearchView& search, const Vec<Real, 3>& centre,
                                      Real centre_squared_distance, const Vec<Real, 3>* x, NearestTriangle* nearest) {
  using V = Vec<Real, 3>;
  V lo = x[0], hi = x[0];
  Real rho2 = Real(0);
  for (int i = 0; i < Points; ++i) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = x[i][k] < lo[k] ? x[i][k] : lo[k];
      hi[k] = x[i][k] > hi[k] ? x[i][k] : hi[k];
    }
    const Real r2 = squared_norm(x[i] - centre);
    rho2 = r2 > rho2 ? r2 : rho2;
  }
  constexpr Real eps_real = std::numeric_limits<Real>::epsilon();
  constexpr Real eps_float = Real(std::numeric_limits<float>::epsilon());
  const Real rho = std::sqrt(rho2) * (Real(1) + Real(16) * eps_real);
  const Real reach = (std::sqrt(centre_squared_distance) + rho) * (Real(1) + Real(1e-4)) +
                     Real(1e-30);  // R, with slack for round-off
  const Real reach2 = reach * reach;
  const Real centre_reach2 = (reach + rho) * (reach + rho);

  // 1. Candidates, sorted by their distance from the centre.
  std::uint32_t found[batch_nearest_capacity];
  Real found_distance[batch_nearest_capacity];
  int count = 0;
  Real cut = std::numeric_limits<Real>::infinity();
  std::uint32_t stack[bvh_max_depth + 2];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::uint32_t index = stack[--top];
    const BvhNode<3> node = search.nodes[index];
    if (detail::box_box_squared_distance(lo, hi, node.lo, node.hi) > reach2) continue;
    if (!node.is_leaf()) {
      stack[top++] = node.right_or_first;
      stack[top++] = index + 1;
      continue;
    }
    for (std::uint32_t k = node.right_or_first; k < node.right_or_first + node.count; ++k) {
      const TriangleCorners& c = search.corners[k];
      V tlo = c.corner[0], thi = c.corner[0];
      for (int q = 1; q < 3; ++q)
        for (int a = 0; a < 3; ++a) {
          tlo[a] = c.corner[q][a] < tlo[a] ? c.corner[q][a] : tlo[a];
          thi[a] = c.corner[q][a] > thi[a] ? c.corner[q][a] : thi[a];
        }
      if (detail::box_box_squared_distance(lo, hi, tlo, thi) > reach2) continue;
      const ClosestPoint<Real, 3> cp = closest_point_on_triangle(centre, c.corner[0], c.corner[1], c.corner[2]);
      const Real d2 = squared_distance(centre, cp.point);
      if (d2 > centre_reach2) continue;
      // Insertion into the sorted list; when it is full, the farthest goes and `cut` keeps the
      // smallest distance that went.
      const Real d = std::sqrt(d2);
      if (count == batch_nearest_capacity) {
        if (!(d < found_distance[count - 1])) {
          cut = d < cut ? d : cut;
          continue;
        }
        cut = found_distance[count - 1] < cut ? found_distance[count - 1] : cut;
        --count;
      }
      int slot = count++;
      for (; slot > 0 && found_distance[slot - 1] > d; --slot) {
        found[slot] = found[slot - 1];
        found_distance[slot] = found_distance[slot - 1];
      }
      found[slot] = k;
      found_distance[slot] = d;
    }
  }
  if (count == 0) {  // cannot happen (the centre's nearest triangle passes both tests); for safety
    for (int i = 0; i < Points; ++i) nearest[i] = search.nearest(x[i]);
    return;
  }
  detail::BatchTriangles t;
  t.count = 0;
  Real far = Real(0);
  for (int j = 0; j < count; ++j) {
    const TriangleCorners& c = search.corners[found[j]];
    const Real corner = detail::add_batch_triangle(t, found[j], c.corner[0] - centre, c.corner[1] - centre,
                                                   c.corner[2] - centre);
    far = corner > far ? corner : far;
    // Rounded down by far more than the float roundings of lower - r in the filter.
    t.lower[j] = float(found_distance[j] * (Real(1) - Real(1e-5)));
  }

  // 2. Float filter.
  Real magnitude = Real(0);
  for (int k = 0; k < 3; ++k) magnitude = std::fabs(centre[k]) > magnitude ? std::fabs(centre[k]) : magnitude;
  const Real scale = rho + far;
  const Real delta = Real(64) * eps_float * scale + Real(64) * eps_real * (Real(2) * magnitude + scale);
  const float margin = float(Real(2) * ((Real(2) * reach + delta) * delta + Real(16) * eps_float * reach2));
  float px[Points], py[Points], pz[Points], r[Points], best[Points];
  for (int i = 0; i < Points; ++i) {
    const V d = x[i] - centre;
    px[i] = float(d[0]), py[i] = float(d[1]), pz[i] = float(d[2]);
    r[i] = float(norm(d) * (Real(1) + Real(1e-5))) + float(Real(1e-5) * rho);
    best[i] = std::numeric_limits<float>::infinity();
  }
  float rows[batch_nearest_capacity * Points];
  constexpr int lanes = UNISPH_BATCH_FILTER_LANES;
  int processed[Points / lanes];
  detail::batch_filter<Points>(t, px, py, pz, r, margin, rows, best, processed);

  // 3. Exact, for the candidates within the margin of each point's float minimum.
  for (int i = 0; i < Points; ++i) {
    const V& p = x[i];
    const float threshold = best[i] + margin;
    NearestTriangle b{p, std::numeric_limits<Real>::infinity(), UINT32_MAX, 0, Feature::face};
    const int evaluated = processed[i / lanes];
    // A point whose group went through the whole list of a list that was cut: its nearest may be
    // among the triangles that went, unless the first of them is too far to be within the margin.
    if (evaluated == count && cut < std::numeric_limits<Real>::infinity()) {
      const Real a = cut * (Real(1) - Real(1e-5)) - Real(r[i]);
      if (!(a > Real(0) && a * a > Real(best[i]) + Real(margin))) {
        nearest[i] = search.nearest(p);
        continue;
      }
    }
    // The candidates within the margin, listed without a branch per candidate (about one per point).
    int within[batch_nearest_capacity];
    int listed = 0;
    for (int j = 0; j < evaluated; ++j) {
      within[listed] = j;
      listed += rows[j * Points + i] - t.slack[j] <= threshold ? 1 : 0;
    }
    for (int w = 0; w < listed; ++w) {
      const std::uint32_t k = t.position[within[w]];
      const TriangleCorners& c = search.corners[k];
      const ClosestPoint<Real, 3> cp = closest_point_on_triangle(p, c.corner[0], c.corner[1], c.corner[2]);
      const Real d2 = squared_distance(p, cp.point);
      const std::uint32_t index = search.triangle_index[k];
      if (d2 < b.squared_distance || (d2 == b.squared_distance && index < b.triangle)) b = {cp.point, d2, index, k, cp.feature};
    }
    nearest[i] = b;
  }
}

// The same, with the centre's distance from a nearest query.
template <int Points>
UNISPH_HOST_DEVICE void batch_nearest(const TriangleMeshSearchView& search, const Vec<Real, 3>& centre,
                                      const Vec<Real, 3>* x, NearestTriangle* nearest) {
  batch_nearest<Points>(search, centre, search.nearest(centre).squared_distance, x, nearest);
}

}  // namespace unisph
