#pragma once
// One layer of a level set as kernels see it: the signed distance phi and its normal at the
// data points of a package mesh, and probes at any position by (bi/tri)linear interpolation of
// the 2^D data points around it, which may lie in up to 2^D different packages.
//
// resolves(x) says whether all of those points belong to packages with data; elsewhere the
// interpolation would mix in the far-field value, and a multi-resolution probe asks a coarser
// layer instead.

#include <cstdint>
#include <type_traits>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/grid/cell_tag.hpp"
#include "unisph/grid/package_grid.hpp"
#include "unisph/memory/view.hpp"

namespace unisph {

template <int D>
struct LevelSetLayerView {
  PackageGrid<D> grid;
  View<const std::uint32_t> cell_package;
  View<const Real> phi;            // packages * 4^D
  View<const Vec<Real, D>> normal; // packages * 4^D
  View<const Real> kernel_weight;  // packages * 4^D
  View<const Vec<Real, D>> kernel_gradient;
  Real far_field_distance;         // |phi| held by the far-field packages

  // The package a cell points to; cells beyond the grid are outside.
  UNISPH_HOST_DEVICE std::uint32_t package_of_cell(const Vec<int, D>& cell) const {
    return grid.contains(cell) ? cell_package[grid.linear(cell)] : outside_package;
  }
  // Where the global data point `point` is stored.
  UNISPH_HOST_DEVICE Index storage_of(const Vec<int, D>& point) const {
    Vec<int, D> cell, local;
    for (int k = 0; k < D; ++k) {
      cell[k] = point[k] >= 0 ? point[k] / package_size : -((-point[k] + package_size - 1) / package_size);
      local[k] = point[k] - cell[k] * package_size;
    }
    return Index(package_of_cell(cell)) * package_points<D> + local_point_index<D>(local);
  }
  UNISPH_HOST_DEVICE bool has_data(const Vec<int, D>& point) const {
    return storage_of(point) >= Index(far_field_packages) * package_points<D>;
  }

  // The lower corner of the interpolation stencil and the weights along each axis.
  UNISPH_HOST_DEVICE void stencil(const Vec<Real, D>& x, Vec<int, D>& lower, Vec<Real, D>& weight) const {
    for (int k = 0; k < D; ++k) {
      const Real s = (x[k] - grid.origin[k]) / grid.data_spacing - Real(0.5);
      const long long t = (long long)s;
      const long long f = Real(t) > s ? t - 1 : t;
      lower[k] = int(f);
      weight[k] = s - Real(f);
    }
  }

  UNISPH_HOST_DEVICE bool resolves(const Vec<Real, D>& x) const {
    Vec<int, D> lower;
    Vec<Real, D> weight;
    stencil(x, lower, weight);
    for (int corner = 0; corner < (1 << D); ++corner) {
      Vec<int, D> point = lower;
      for (int k = 0; k < D; ++k) point[k] += (corner >> k) & 1;
      if (!has_data(point)) return false;
    }
    return true;
  }

  template <class T>
  UNISPH_HOST_DEVICE T interpolate(View<const T> values, const Vec<Real, D>& x) const {
    Vec<int, D> lower;
    Vec<Real, D> weight;
    stencil(x, lower, weight);
    T sum{};
    for (int corner = 0; corner < (1 << D); ++corner) {
      Vec<int, D> point = lower;
      Real w = Real(1);
      for (int k = 0; k < D; ++k) {
        const int bit = (corner >> k) & 1;
        point[k] += bit;
        w *= bit ? weight[k] : Real(1) - weight[k];
      }
      sum = sum + values[storage_of(point)] * w;
    }
    return sum;
  }

  UNISPH_HOST_DEVICE Real probe_phi(const Vec<Real, D>& x) const { return interpolate(phi, x); }
  UNISPH_HOST_DEVICE Real probe_kernel_weight(const Vec<Real, D>& x) const { return interpolate(kernel_weight, x); }
  UNISPH_HOST_DEVICE Vec<Real, D> probe_kernel_gradient(const Vec<Real, D>& x) const {
    return interpolate(kernel_gradient, x);
  }
  // The kernel integrals (kernel_integrals.hpp) at x by cubic Hermite interpolation of the
  // weight from the weight and its gradient at the 2^D data points around x (tensor product,
  // zero cross derivatives): continuous with a continuous gradient across cells and packages,
  // and the gradient returned is the exact gradient of the weight returned, so that particles
  // relaxing against them (relaxation_surface.hpp) follow a force with an energy.
  struct KernelIntegrals {
    Real weight;
    Vec<Real, D> gradient;
  };
  UNISPH_HOST_DEVICE KernelIntegrals probe_kernel_integrals(const Vec<Real, D>& x) const {
    Vec<int, D> lower;
    Vec<Real, D> t;
    stencil(x, lower, t);
    const Real spacing = grid.data_spacing;
    KernelIntegrals result{Real(0), Vec<Real, D>{}};
    for (int corner = 0; corner < (1 << D); ++corner) {
      Vec<int, D> point = lower;
      // Per axis: value basis V and its t-derivative dV, derivative basis B (times the spacing)
      // and its t-derivative dB.
      Real V[D], dV[D], B[D], dB[D];
      for (int k = 0; k < D; ++k) {
        const int bit = (corner >> k) & 1;
        point[k] += bit;
        const Real u = t[k], u2 = u * u, u3 = u2 * u;
        if (bit == 0) {
          V[k] = Real(1) - Real(3) * u2 + Real(2) * u3;
          dV[k] = Real(6) * (u2 - u);
          B[k] = u - Real(2) * u2 + u3;
          dB[k] = Real(1) - Real(4) * u + Real(3) * u2;
        } else {
          V[k] = Real(3) * u2 - Real(2) * u3;
          dV[k] = Real(6) * (u - u2);
          B[k] = u3 - u2;
          dB[k] = Real(3) * u2 - Real(2) * u;
        }
      }
      const Index at = storage_of(point);
      const Real f = kernel_weight[at];
      const Vec<Real, D> g = kernel_gradient[at];
      // weight: f Π V_k + Σ_m spacing g_m B_m Π_{k≠m} V_k
      Real all = Real(1);
      for (int k = 0; k < D; ++k) all *= V[k];
      Real value = f * all;
      for (int m = 0; m < D; ++m) {
        Real product = spacing * g[m] * B[m];
        for (int k = 0; k < D; ++k)
          if (k != m) product *= V[k];
        value += product;
      }
      result.weight += value;
      // d/dx_j of the same: the factor of axis j differentiated (d/dx_j = d/dt_j / spacing)
      for (int j = 0; j < D; ++j) {
        Real term = f * dV[j] / spacing;
        for (int k = 0; k < D; ++k)
          if (k != j) term *= V[k];
        for (int m = 0; m < D; ++m) {
          Real product = g[m] * (m == j ? dB[m] : B[m] * dV[j]);
          for (int k = 0; k < D; ++k)
            if (k != m && k != j) product *= V[k];
          term += product;
        }
        result.gradient[j] += term;
      }
    }
    return result;
  }

  // The interpolated normal, made unit again (zero where it vanishes).
  UNISPH_HOST_DEVICE Vec<Real, D> probe_normal(const Vec<Real, D>& x) const {
    const Vec<Real, D> n = interpolate(normal, x);
    const Real length = norm(n);
    return length > Real(0) ? n / length : n;
  }
};
static_assert(std::is_trivially_copyable_v<LevelSetLayerView<3>>,
              "a level-set view is captured by value into kernels, so it must be trivially copyable.");

}  // namespace unisph
