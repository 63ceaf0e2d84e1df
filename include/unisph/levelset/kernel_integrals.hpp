#pragma once
// Integrals of the SPH smoothing kernel over the region outside the shape, at every data point:
//
//   weight(x)   = ∫_{phi > 0} W(x - y) dy     0 deep inside, 1 far outside
//   gradient(x) = ∫_{phi > 0} ∇W(x - y) dy    ∇ with respect to x; zero away from the surface
//
// what particle relaxation uses as the missing part of a particle's kernel support next to a
// wall. Two parts:
//   - the tangent half-space: phi linear with the point's own phi and normal, whose integrals
//     are known in closed form, F(phi) and W1(phi) n, with W1 the kernel's marginal along one
//     axis and F its integral (evaluated by Gauss-Legendre quadrature, exact in 3D where the
//     integrands are polynomials);
//   - a correction for the geometry's departure from that plane: a midpoint sum of W (and ∇W)
//     over the sub-cells (kernel_integral_subdivision per axis) of the cells around the point,
//     each weighted by the fraction of the sub-cell lying outside (a linear ramp in phi over the
//     sub-cell, phi multilinearly interpolated from the data points to the sub-cell's centre),
//     minus the same sum for the tangent plane. The discretisation error of the sum cancels
//     where the surface is flat, so a flat wall gives the exact integrals, and curved walls,
//     edges and corners change them by what the interpolated phi sees.
//     Why sub-cells with interpolated phi: the outside the integrals describe is then the region
//     where the probed (interpolated) phi is positive, the same region that particle relaxation
//     keeps its particles out of (RelaxationSurface::bound). With one sample per cell and phi
//     taken linear from each cell's own point, the integrals next to a convex corner came out
//     short of that region's (by up to 0.1 in weight on plate_with_holes.poly at dx 0.1), so
//     the particle at each corner was pushed out of the body and held on the surface by the
//     bounding with a residual 23-80x the next largest (docs/particle_generation.md, "Corners").
// The kernel is Wendland C2 with the smoothing length given; the sum reaches at most 3 data
// points each way (the interpolation then stays inside the 3^D packages around a point), so on
// a layer whose spacing is too coarse for the cutoff the far end of the support is left to the
// tangent plane.

#include <cmath>
#include <cstdint>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/grid/neighbour_index_shift.hpp"
#include "unisph/memory/view.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"

namespace unisph {

// Fraction of the cube of side `spacing` centred at a data point on the side phi > 0, for phi
// linear with unit gradient `normal` across it: a linear ramp over the range phi takes there.
template <int D>
UNISPH_HOST_DEVICE inline Real cut_cell_outside_fraction(Real phi, const Vec<Real, D>& normal, Real spacing) {
  Real extent = Real(0);
  for (int k = 0; k < D; ++k) extent += normal[k] < Real(0) ? -normal[k] : normal[k];
  if (extent == Real(0)) return phi > Real(0) ? Real(1) : Real(0);
  const Real fraction = Real(0.5) + phi / (spacing * extent);
  return fraction < Real(0) ? Real(0) : (fraction > Real(1) ? Real(1) : fraction);
}

// Cells each way the correction sum reaches: with the data points one further each way for the
// interpolation, inside the 3^D packages around a point.
inline constexpr int kernel_integral_reach = package_size - 1;
// Sub-cells per axis of the correction sum (2: 8 sub-cells per cell in 3D).
inline constexpr int kernel_integral_subdivision = 2;

// The half-space integrals of a Wendland C2 kernel as functions of the signed distance s of x
// from the plane (positive outside).
template <int D>
struct HalfSpaceKernelIntegral {
  WendlandC2Kernel<Real, D> kernel;

  // Gauss-Legendre nodes and weights on [-1, 1]: 4 points in 3D (exact: polynomial integrands),
  // 8 points in 2D.
  static constexpr int points = D == 3 ? 4 : 8;
  UNISPH_HOST_DEVICE static Real node(int i) {
    constexpr double n4[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
    constexpr double n8[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                              0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
    return Real(D == 3 ? n4[i] : n8[i]);
  }
  UNISPH_HOST_DEVICE static Real gauss_weight(int i) {
    constexpr double w4[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
    constexpr double w8[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
                              0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
    return Real(D == 3 ? w4[i] : w8[i]);
  }

  // W1(t): the kernel integrated over the plane (3D) or line (2D) at distance t.
  UNISPH_HOST_DEVICE Real marginal(Real t) const {
    const Real a = t < Real(0) ? -t : t, R = kernel.cutoff();
    if (a >= R) return Real(0);
    Real sum = Real(0);
    if constexpr (D == 3) {
      // 2 pi ∫_a^R W(r) r dr
      const Real half = Real(0.5) * (R - a), mid = Real(0.5) * (R + a);
      for (int i = 0; i < points; ++i) {
        const Real r = mid + half * node(i);
        sum += gauss_weight(i) * kernel.value(r) * r;
      }
      return Real(2) * Real(3.14159265358979323846) * half * sum;
    } else {
      // 2 ∫_0^sqrt(R^2 - a^2) W(sqrt(a^2 + u^2)) du
      const Real top = std::sqrt(R * R - a * a), half = Real(0.5) * top;
      for (int i = 0; i < points; ++i) {
        const Real u = half + half * node(i);
        sum += gauss_weight(i) * kernel.value(std::sqrt(a * a + u * u));
      }
      return Real(2) * half * sum;
    }
  }
  // F(s) = ∫_{-R}^{s} W1(t) dt: the kernel's integral over the half-space s > (distance of y).
  UNISPH_HOST_DEVICE Real weight(Real s) const {
    const Real R = kernel.cutoff();
    if (s <= -R) return Real(0);
    if (s >= R) return Real(1);
    // W1 is even: F(s) = 1/2 - ∫_s^0 W1 for s < 0, 1/2 + ∫_0^s W1 for s > 0.
    const Real a = s < Real(0) ? -s : s, half = Real(0.5) * a;
    Real sum = Real(0);
    for (int i = 0; i < points; ++i) sum += gauss_weight(i) * marginal(half + half * node(i));
    const Real part = half * sum;
    return s < Real(0) ? Real(0.5) - part : Real(0.5) + part;
  }
};

// The sub-cell centres of the correction sum, relative to a data point in units of the spacing:
// cell offset a (integer) plus (i + 1/2) / s - 1/2 per axis.
UNISPH_HOST_DEVICE inline Real sub_cell_offset(int cell, int sub) {
  return Real(cell) + (Real(sub) + Real(0.5)) / Real(kernel_integral_subdivision) - Real(0.5);
}

// Sum of W over the sub-cell centres of all space around a point (the normalisation of the
// correction sum: Σ W V_sub ≈ 1, made exact).
template <int D>
inline Real sub_cell_lattice_sum(const WendlandC2Kernel<Real, D>& kernel, Real spacing) {
  const int s = kernel_integral_subdivision;
  const int reach = int(std::ceil(double(kernel.cutoff()) / double(spacing))) + 1;
  const int width = 2 * reach + 1;
  long long count = 1;
  for (int k = 0; k < D; ++k) count *= width * s;
  double sum = 0;
  for (long long c = 0; c < count; ++c) {
    long long rest = c;
    double r2 = 0;
    for (int k = 0; k < D; ++k) {
      const int i = int(rest % (width * s));
      rest /= width * s;
      const double o = double(sub_cell_offset(i / s - reach, i % s)) * double(spacing);
      r2 += o * o;
    }
    sum += double(kernel.value(Real(std::sqrt(r2))));
  }
  return Real(sum);
}

template <int D>
struct KernelIntegralsAtDataPoints {
  View<const Real> phi;
  View<const Vec<Real, D>> normal;
  View<const PackageNeighbourhood<D>> neighbourhood;
  View<Real> weight;
  View<Vec<Real, D>> gradient;
  HalfSpaceKernelIntegral<D> half_space;
  Real spacing;
  Real lattice_sum;  // sum of W over the sub-cell centres of all space (sub_cell_lattice_sum)

  static constexpr int sub = kernel_integral_subdivision;
  static constexpr int block_points = D == 3 ? 27 : 9;  // the data points around a cell's own

  UNISPH_HOST_DEVICE void operator()(std::uint32_t package, int local_point) const {
    const Index self = Index(package) * package_points<D> + local_point;
    const Real phi0 = phi[self];
    const Vec<Real, D> n0 = normal[self];
    const Real cutoff = half_space.kernel.cutoff();
    // Beyond the cutoff plus a cell the support lies wholly on one side.
    const Real reach = cutoff + spacing;
    if (phi0 > reach || phi0 < -reach) {
      weight[self] = phi0 > Real(0) ? Real(1) : Real(0);
      gradient[self] = Vec<Real, D>{};
      return;
    }
    Vec<int, D> local;
    int rest = local_point;
    for (int k = 0; k < D; ++k) {
      local[k] = rest % package_size;
      rest /= package_size;
    }
    // Cells whose sub-cell centres can lie within the cutoff: |a| - (1/2 - 1/(2s)) < cutoff.
    int steps = int(cutoff / spacing + Real(0.5) - Real(0.5) / Real(sub));
    steps = steps > kernel_integral_reach ? kernel_integral_reach : steps;
    const int width = 2 * steps + 1;
    int count = 1;
    for (int k = 0; k < D; ++k) count *= width;
    const bool has_plane = n0 != Vec<Real, D>{};
    Real plane_extent = Real(0);
    for (int k = 0; k < D; ++k) plane_extent += n0[k] < Real(0) ? -n0[k] : n0[k];
    const Real sub_spacing = spacing / Real(sub);
    // phi (a distance: Lipschitz 1) at a sub-cell centre, interpolated from the data points within
    // one of the cell's own, differs from the cell's by at most sqrt(D) spacing; beyond that plus
    // the ramp's half width every sub-cell of the cell lies on the cell's side.
    const Real cell_uniform = std::sqrt(Real(D)) * (spacing + Real(0.5) * sub_spacing);
    // The tangent plane across a cell: at most extent (1/2 - 1/(2s)) spacing plus the ramp's half width.
    const Real plane_uniform = plane_extent * Real(0.5) * spacing;
    Real sum = Real(0);
    Vec<Real, D> sum_gradient{};
    const PackageNeighbourhood<D> around = neighbourhood[package];
    for (int s = 0; s < count; ++s) {
      Vec<int, D> offset;
      int r = s;
      Real plane_cell = phi0;
      for (int k = 0; k < D; ++k) {
        offset[k] = r % width - steps;
        r /= width;
        plane_cell += n0[k] * Real(offset[k]) * spacing;
      }
      Vec<int, D> at = local;
      for (int k = 0; k < D; ++k) at[k] += offset[k];
      const DataPointAddress a = neighbour_index_shift<D>(at, around);
      const Index cell = Index(a.package) * package_points<D> + a.local_point;
      const Real phi_cell = phi[cell];
      const bool cell_one_side = phi_cell >= cell_uniform || phi_cell <= -cell_uniform;
      const bool plane_one_side = !has_plane || plane_cell >= plane_uniform || plane_cell <= -plane_uniform;
      const bool cell_outside = phi_cell > Real(0);
      const bool plane_outside = has_plane && plane_cell > Real(0);
      if (cell_one_side && plane_one_side && cell_outside == plane_outside) continue;
      // The data points around the cell's own, for the interpolation.
      Real block[block_points];
      if (!cell_one_side)
        for (int b = 0; b < block_points; ++b) {
          const DataPointAddress c = neighbour_index_shift<D>(neighbour_in_block<D>(at, b), around);
          block[b] = phi[Index(c.package) * package_points<D> + c.local_point];
        }
      const Vec<Real, D> n_cell = normal[cell];
      int sub_count = 1;
      for (int k = 0; k < D; ++k) sub_count *= sub;
      for (int u = 0; u < sub_count; ++u) {
        Vec<Real, D> y;  // the sub-cell centre relative to the data point, in spacings
        Vec<int, D> index;
        int q = u;
        Real distance2 = Real(0);
        for (int k = 0; k < D; ++k) {
          index[k] = q % sub;
          q /= sub;
          y[k] = sub_cell_offset(offset[k], index[k]);
          distance2 += y[k] * y[k];
        }
        const Real distance = std::sqrt(distance2) * spacing;
        if (distance >= cutoff) continue;
        Real fraction;
        if (cell_one_side) {
          fraction = cell_outside ? Real(1) : Real(0);
        } else {
          // Multilinear interpolation in the block: the sub-cell centre lies at t = y - offset in
          // (-1/2, 1/2) of the cell's own point, between block index 0/1 (t < 0) or 1/2.
          Real value = Real(0);
          int lower[D];
          Real w[D];
          for (int k = 0; k < D; ++k) {
            const Real t = y[k] - Real(offset[k]);
            lower[k] = t < Real(0) ? 0 : 1;
            w[k] = t < Real(0) ? t + Real(1) : t;
          }
          for (int corner = 0; corner < (1 << D); ++corner) {
            int b = 0, stride = 1;
            Real cw = Real(1);
            for (int k = 0; k < D; ++k) {
              const int bit = (corner >> k) & 1;
              b += (lower[k] + bit) * stride;
              stride *= 3;
              cw *= bit ? w[k] : Real(1) - w[k];
            }
            value += block[b] * cw;
          }
          fraction = cut_cell_outside_fraction<D>(value, n_cell, sub_spacing);
        }
        if (has_plane) {
          Real plane_phi = phi0;
          for (int k = 0; k < D; ++k) plane_phi += n0[k] * y[k] * spacing;
          fraction -= cut_cell_outside_fraction<D>(plane_phi, n0, sub_spacing);
        }
        if (fraction == Real(0)) continue;
        sum += half_space.kernel.value(distance) * fraction;
        // ∇_x W(x - y) = W'(r) (x - y) / r, and x - y = -y * spacing (r > 0: the centres are off the point).
        const Real scale = -half_space.kernel.derivative(distance) * fraction * spacing / distance;
        for (int k = 0; k < D; ++k) sum_gradient[k] += scale * y[k];
      }
    }
    if (has_plane) {
      weight[self] = half_space.weight(phi0) + sum / lattice_sum;
      gradient[self] = n0 * half_space.marginal(phi0) + sum_gradient / lattice_sum;
    } else {
      weight[self] = sum / lattice_sum;
      gradient[self] = sum_gradient / lattice_sum;
    }
  }
};

}  // namespace unisph
