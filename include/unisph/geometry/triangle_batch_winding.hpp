#pragma once
// The winding-number side (TriangleMeshSearchView::winding_number(p) > 1/2) of every point of a
// small batch of nearby points (a package's 64 data points, a coarse cell's 8 children) with one
// walk of the BVH for the whole batch, and with the decision the per-point sum would take.
//
//   1. Walk. The per-point sum visits the BVH top down and takes a cluster as one dipole term
//      where the point is farther than far_field_ratio times its radius from the cluster's
//      centre (that test in Real, exactly as winding_number does it), else its children or, at a
//      leaf, its triangles' solid angles. The batch walks the tree once with the set of points
//      still descending: a cluster is far (or near) for all of them at once where the batch's
//      ball around its centre lies wholly outside (inside) the cluster's ball, with a relative
//      margin of 1000 Real epsilons over the roundings; otherwise each point takes the same test
//      as winding_number. So every point sums the same terms as its own walk would.
//   2. Terms, in float, four points at a time (one SSE vector): the dipole term and the solid
//      angle 2 atan2(N, D) (Van Oosterom & Strackee, as solid_angle), with a polynomial atan
//      (Abramowitz & Stegun 4.4.49) and coordinates relative to the batch's centre. Each term
//      comes with a bound of its error against the Real term: the roundings of the relative
//      coordinates (2 eps (|a - c|_1 + |p - c|_1) per vector) carried through N, D (first order,
//      times 8/6 for the rest) and the dipole, plus 64 eps of the magnitudes for the arithmetic,
//      plus the atan's own error. A solid angle whose (N, D) may lie across the branch cut of
//      atan2 (|N| <= E and D <= E: the point lies on the triangle within the error) or within
//      ten errors of (0, 0) gives no bound: the point is decided by the per-point sum.
//   3. Decision. The float sum and its bound (the terms' bounds plus the roundings of the sum, 2
//      n eps sum |term|, which also covers the Real sum's own): where |sum - 2 pi| exceeds the
//      bound plus 1e-5, the side is the float sum's, which is then the side of the Real sum; the
//      other points (about none away from holes of open meshes and points on the surface) are
//      decided by TriangleMeshSearchView::winding_number itself.
//
// Host code for GCC and Clang (the vector extension); elsewhere, and in CUDA translation units,
// each point's winding_number. Launched on the host policies only; the GPU keeps one thread per
// point.

#include <cstdint>
#include <cstring>
#include <limits>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/geometry/bvh.hpp"
#include "unisph/geometry/triangle_mesh_search_view.hpp"
#include "unisph/geometry/winding_number.hpp"

#if defined(__GNUC__) && !defined(__CUDA_ARCH__)
#define UNISPH_BATCH_WINDING_VECTOR 1
#if defined(__SSE__)
#include <xmmintrin.h>
#endif
#else
#define UNISPH_BATCH_WINDING_VECTOR 0
#endif

namespace unisph {

#if UNISPH_BATCH_WINDING_VECTOR
namespace detail {
typedef float winding_lanes __attribute__((vector_size(16)));
typedef std::int32_t winding_mask __attribute__((vector_size(16)));

inline winding_lanes winding_sqrt(winding_lanes v) {
#if defined(__SSE__)
  winding_lanes r;
  const __m128 s = _mm_sqrt_ps(reinterpret_cast<const __m128&>(v));
  std::memcpy(&r, &s, sizeof(r));
  return r;
#else
  for (int k = 0; k < 4; ++k) v[k] = __builtin_sqrtf(v[k]);
  return v;
#endif
}
inline winding_lanes winding_abs(winding_lanes v) { return v < 0.0f ? -v : v; }
inline winding_lanes winding_min(winding_lanes a, winding_lanes b) { return a < b ? a : b; }
inline winding_lanes winding_max(winding_lanes a, winding_lanes b) { return a > b ? a : b; }

// atan2(y, x) in float, four lanes, given a = min(|x|, |y|) / max(|x|, |y|) (0 where both are
// 0): the polynomial of Abramowitz & Stegun 4.4.47 (|error| <= 1e-5 on [0, 1]). Error at most
// batch_winding_atan_error (measured: at most 1.17e-5 over 2 10^7 random arguments of
// magnitudes 2^-30 to 2^30; the bound leaves a factor 2.5). Lanes with y = -0 give +pi, not -pi: the caller
// never uses them (they lie on the branch cut).
inline constexpr float batch_winding_atan_error = 3e-5f;
inline winding_lanes winding_atan2(winding_lanes y, winding_lanes x, winding_lanes a) {
  const winding_lanes ax = winding_abs(x), ay = winding_abs(y);
  const winding_lanes zero = winding_lanes{} * 0.0f;
  const winding_lanes s = a * a;
  winding_lanes p = zero + 0.0208351f;
  p = p * s - 0.0851330f;
  p = p * s + 0.1801410f;
  p = p * s - 0.3302995f;
  p = p * s + 0.9998660f;
  p = p * a;
  p = ay > ax ? 1.57079632679489662f - p : p;
  p = x < zero ? 3.14159265358979324f - p : p;
  return y < zero ? -p : p;
}

// Four consecutive points (one vector lane each) and their L1 norms, loaded from the
// structure-of-arrays copies at `first`.
struct winding_group {
  winding_lanes x, y, z, norm;
};
inline winding_group load_winding_group(const float* px, const float* py, const float* pz, const float* pn, int first) {
  winding_group g;
  std::memcpy(&g.x, px + first, sizeof(winding_lanes));
  std::memcpy(&g.y, py + first, sizeof(winding_lanes));
  std::memcpy(&g.z, pz + first, sizeof(winding_lanes));
  std::memcpy(&g.norm, pn + first, sizeof(winding_lanes));
  return g;
}

inline winding_mask winding_lane_mask(unsigned bits) {
  return winding_mask{-std::int32_t(bits & 1u), -std::int32_t((bits >> 1) & 1u), -std::int32_t((bits >> 2) & 1u),
                      -std::int32_t((bits >> 3) & 1u)};
}
}  // namespace detail
#endif

// inside[i] = search.winding_number(x[i]) > 1/2 for every point i whose bit is set in `wanted`
// (the others are left as they are); the points should lie close together around `centre`.
template <int Points>
UNISPH_HOST_DEVICE void batch_winding_inside(const TriangleMeshSearchView& search, const Vec<Real, 3>& centre, const Vec<Real, 3>* x,
                          std::uint64_t wanted, bool* inside) {
  static_assert(Points <= 64 && Points % 4 == 0, "up to 64 points, in whole vectors of four");
#if !UNISPH_BATCH_WINDING_VECTOR
  for (int i = 0; i < Points; ++i)
    if ((wanted >> i) & 1u) inside[i] = search.winding_number(x[i]) > Real(0.5);
#else
  using V = Vec<Real, 3>;
  using F = detail::winding_lanes;
  constexpr int groups = Points / 4;
  if (wanted == 0) return;
  constexpr float eps = std::numeric_limits<float>::epsilon() + float(std::numeric_limits<Real>::epsilon());
  const F zero = F{} * 0.0f;

  // The points relative to the centre, in float, with the L1 norms (rounded up) for the bounds.
  alignas(16) float px[Points], py[Points], pz[Points], pn[Points];
  Real rho2 = Real(0);
  for (int i = 0; i < Points; ++i) {
    const V d = x[i] - centre;
    px[i] = float(d[0]), py[i] = float(d[1]), pz[i] = float(d[2]);
    pn[i] = float((std::fabs(d[0]) + std::fabs(d[1]) + std::fabs(d[2])) * Real(1.0001));
    const Real r2 = squared_norm(d);
    rho2 = r2 > rho2 ? r2 : rho2;
  }
  const Real rho = std::sqrt(rho2) * (Real(1) + Real(16) * std::numeric_limits<Real>::epsilon());
  constexpr Real margin = Real(1000) * std::numeric_limits<Real>::epsilon();

  F angle[groups], bound[groups], magnitude[groups], terms[groups];
  std::int32_t undecided[groups];
  for (int g = 0; g < groups; ++g) angle[g] = bound[g] = magnitude[g] = terms[g] = zero, undecided[g] = 0;

  // Clusters far for every point and farther than 8 rho from the centre: one term for all, by
  // Taylor: t(c + h) = t0 - g.h + remainder, t0 = a.R / |R|^3, g = a / |R|^3 - 3 (a.R) R / |R|^5
  // (R = C - c), |remainder| <= 3 |a| rho^2 / (|R| - rho)^4 (the third derivatives of 1 / |r|
  // are at most 3! / |r|^4 in any directions); summed in Real.
  Real shared_t = Real(0), shared_bound = Real(0), shared_magnitude = Real(0), shared_terms = Real(0);
  V shared_g{};
  struct Entry {
    std::uint32_t node;
    std::uint64_t points;
  };
  Entry stack[bvh_max_depth + 2];
  int top = 0;
  stack[top++] = {0, wanted};
  while (top > 0) {
    const Entry e = stack[--top];
    const WindingCluster cluster = search.clusters[e.node];
    const Real threshold2 = search.far_field_ratio * search.far_field_ratio * cluster.radius * cluster.radius;
    const V to_cluster = cluster.centre - centre;
    const Real dc = norm(to_cluster);
    std::uint64_t far = 0, near = 0;
    if (dc > rho && (dc - rho) * (dc - rho) > threshold2 * (Real(1) + margin)) {
      far = e.points;
    } else if ((dc + rho) * (dc + rho) < threshold2 * (Real(1) - margin)) {
      near = e.points;
    } else {
      for (std::uint64_t m = e.points; m != 0; m &= m - 1) {
        const int i = __builtin_ctzll(m);
        const V r = cluster.centre - x[i];
        if (squared_norm(r) > threshold2)
          far |= std::uint64_t(1) << i;
        else
          near |= std::uint64_t(1) << i;
      }
    }
    if (far == wanted && dc > Real(8) * rho) {
      const Real a = norm(cluster.area_normal), d2 = dc * dc, d3 = d2 * dc;
      const Real ar = dot(cluster.area_normal, to_cluster);
      shared_t += ar / d3;
      shared_g += cluster.area_normal / d3 - (Real(3) * ar / (d3 * d2)) * to_cluster;
      const Real gap = dc - rho;
      shared_bound += Real(3) * a * rho * rho / (gap * gap * gap * gap) + Real(16) * Real(eps) * a / (gap * gap);
      shared_magnitude += a / (gap * gap);
      shared_terms += Real(1);
      far = 0;
    }
    if (far != 0) {
      // Dipole terms a.r / |r|^3, r = C - p.
      const float cx = float(to_cluster[0]), cy = float(to_cluster[1]), cz = float(to_cluster[2]);
      const float nx = float(cluster.area_normal[0]), ny = float(cluster.area_normal[1]),
                  nz = float(cluster.area_normal[2]);
      const float an = float(norm(cluster.area_normal) * Real(1.0001));
      const float cn = float((std::fabs(to_cluster[0]) + std::fabs(to_cluster[1]) + std::fabs(to_cluster[2])) * Real(1.0001));
      for (int g = 0; g < groups; ++g) {
        const unsigned bits = unsigned(far >> (4 * g)) & 15u;
        if (bits == 0) continue;
        const detail::winding_mask lanes = detail::winding_lane_mask(bits);
        const detail::winding_group p = detail::load_winding_group(px, py, pz, pn, 4 * g);
        const F X = p.x, Y = p.y, Z = p.z, N1 = p.norm;
        const F rx = cx - X, ry = cy - Y, rz = cz - Z;
        const F d2 = rx * rx + ry * ry + rz * rz;
        const F d = detail::winding_sqrt(d2);
        const F inverse = 1.0f / (d2 * d);
        const F t = (nx * rx + ny * ry + nz * rz) * inverse;
        const F dr = 2.0f * eps * (cn + N1);
        const F err = an * (16.0f * eps * d + 4.4f * dr) * inverse;
        angle[g] += lanes ? t : zero;
        bound[g] += lanes ? err : zero;
        magnitude[g] += lanes ? detail::winding_abs(t) : zero;
        terms[g] += lanes ? zero + 1.0f : zero;
        const detail::winding_mask bad = lanes & (dr > 0.1f * d);
        for (int k = 0; k < 4; ++k) undecided[g] |= bad[k];
      }
    }
    if (near == 0) continue;
    const BvhNode<3> node = search.nodes[e.node];
    if (!node.is_leaf()) {
      stack[top++] = {node.right_or_first, near};
      stack[top++] = {e.node + 1, near};
      continue;
    }
    for (std::uint32_t k = node.right_or_first; k < node.right_or_first + node.count; ++k) {
      const TriangleCorners& c = search.corners[k];
      float q[3][3], qn[3];
      for (int v = 0; v < 3; ++v) {
        const V a = c.corner[v] - centre;
        q[v][0] = float(a[0]), q[v][1] = float(a[1]), q[v][2] = float(a[2]);
        qn[v] = float((std::fabs(a[0]) + std::fabs(a[1]) + std::fabs(a[2])) * Real(1.0001));
      }
      for (int g = 0; g < groups; ++g) {
        const unsigned bits = unsigned(near >> (4 * g)) & 15u;
        if (bits == 0) continue;
        const detail::winding_mask lanes = detail::winding_lane_mask(bits);
        const detail::winding_group p = detail::load_winding_group(px, py, pz, pn, 4 * g);
        const F X = p.x, Y = p.y, Z = p.z, N1 = p.norm;
        const F xx = q[0][0] - X, xy = q[0][1] - Y, xz = q[0][2] - Z;
        const F yx = q[1][0] - X, yy = q[1][1] - Y, yz = q[1][2] - Z;
        const F zx = q[2][0] - X, zy = q[2][1] - Y, zz = q[2][2] - Z;
        const F lx = detail::winding_sqrt(xx * xx + xy * xy + xz * xz);
        const F ly = detail::winding_sqrt(yx * yx + yy * yy + yz * yz);
        const F lz = detail::winding_sqrt(zx * zx + zy * zy + zz * zz);
        const F numerator = xx * (yy * zz - yz * zy) + xy * (yz * zx - yx * zz) + xz * (yx * zy - yy * zx);
        const F m = lx * ly * lz;
        const F denominator = m + (xx * yx + xy * yy + xz * yz) * lz + (yx * zx + yy * zy + yz * zz) * lx +
                              (zx * xx + zy * xy + zz * xz) * ly;
        const F dx = 2.0f * eps * (qn[0] + N1), dy = 2.0f * eps * (qn[1] + N1), dz = 2.0f * eps * (qn[2] + N1);
        const F error = 8.0f * (dx * ly * lz + dy * lx * lz + dz * lx * ly) + 64.0f * eps * m;
        // The error of the angle: at most |d(N, D)| / (r - |d(N, D)|) with r = |(N, D)| >= hi =
        // max(|N|, |D|) and |d(N, D)| <= sqrt(2) E <= 0.15 hi, so at most 1.7 E / hi.
        const F an_ = detail::winding_abs(numerator), ad_ = detail::winding_abs(denominator);
        const F hi = detail::winding_max(an_, ad_);
        const F inverse = 1.0f / (hi > zero ? hi : zero + 1.0f);
        const F t = 2.0f * detail::winding_atan2(numerator, denominator, detail::winding_min(an_, ad_) * inverse);
        const F err = 2.0f * (1.7f * error * inverse + detail::batch_winding_atan_error);
        const detail::winding_mask bad =
            lanes & (((an_ <= error) & (denominator <= error)) | (error > 0.1f * hi) | (dx > 0.1f * lx) |
                     (dy > 0.1f * ly) | (dz > 0.1f * lz));
        angle[g] += lanes ? t : zero;
        bound[g] += lanes ? err : zero;
        magnitude[g] += lanes ? detail::winding_abs(t) : zero;
        terms[g] += lanes ? zero + 1.0f : zero;
        for (int l = 0; l < 4; ++l) undecided[g] |= bad[l] ? (1 << l) : 0;
      }
    }
  }
  // undecided[g] from the dipoles is -1 (every lane) or 0: redo the group's lanes then.
  constexpr float two_pi = 6.28318530717958648f;
  for (int g = 0; g < groups; ++g) {
    for (int l = 0; l < 4; ++l) {
      const int i = 4 * g + l;
      if (!((wanted >> i) & 1u)) continue;
      const V h = x[i] - centre;
      const float shared = float(shared_t - dot(shared_g, h));
      const float total = bound[g][l] + float(shared_bound) +
                          2.0f * (terms[g][l] + float(shared_terms) + 2.0f) * eps *
                              (magnitude[g][l] + float(shared_magnitude) + std::fabs(shared)) +
                          1e-5f;
      const float off = (angle[g][l] + shared) - two_pi;
      if (!((undecided[g] >> l) & 1) && (off > total || off < -total))
        inside[i] = off > 0.0f;
      else
        inside[i] = search.winding_number(x[i]) > Real(0.5);
    }
  }
#endif
}

}  // namespace unisph
