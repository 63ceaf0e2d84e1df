#pragma once
// Wendland C2 smoothing kernel in 2D and 3D with smoothing length h = 1.3 dx (or another ratio h / dx:
// a case's geometry.smoothing_length_ratio) and cutoff 2h:
//   W(q) = alpha / h^D (1 - q/2)^4 (1 + 2q),  q = r / h < 2,
// alpha = 7 / (4 pi) in 2D and 21 / (16 pi) in 3D, so that W integrates to 1.
#include <cmath>
#include <type_traits>

#include "unisph/core/config.hpp"

namespace unisph {

template <class T, int D>
struct WendlandC2Kernel {
  static_assert(std::is_floating_point_v<T>, "The Wendland kernel is evaluated in float or double.");
  static_assert(D == 2 || D == 3, "The Wendland C2 kernel is implemented for 2D and 3D.");

  static constexpr T smoothing_length_ratio = T(1.3);  // h / dx unless a case asks another

  T h = T(1);
  T inverse_h = T(1);
  T normalisation = T(0);  // alpha / h^D

  static WendlandC2Kernel from_spacing(T dx, T ratio = smoothing_length_ratio) {
    WendlandC2Kernel k;
    k.h = ratio * dx;
    k.inverse_h = T(1) / k.h;
    const T pi = T(3.14159265358979323846);
    k.normalisation = D == 2 ? T(7) / (T(4) * pi * k.h * k.h) : T(21) / (T(16) * pi * k.h * k.h * k.h);
    return k;
  }

  UNISPH_HOST_DEVICE T cutoff() const { return T(2) * h; }

  UNISPH_HOST_DEVICE T value(T r) const {
    const T q = r * inverse_h;
    if (q >= T(2)) return T(0);
    const T t = T(1) - T(0.5) * q;
    const T t2 = t * t;
    return normalisation * t2 * t2 * (T(1) + T(2) * q);
  }

  // dW/dr (negative inside the support): -5 q (1 - q/2)^3 alpha / h^(D+1).
  UNISPH_HOST_DEVICE T derivative(T r) const {
    const T q = r * inverse_h;
    if (q >= T(2)) return T(0);
    const T t = T(1) - T(0.5) * q;
    return -T(5) * q * t * t * t * normalisation * inverse_h;
  }

  // Sum of W over a full square/cubic lattice of spacing dx around a particle (itself
  // included): the number density of a particle inside the fluid at rest. Density
  // summation divides by it so that a lattice at rest has exactly the reference density.
  T lattice_sum(T dx) const {
    const int reach = static_cast<int>(std::ceil(cutoff() / dx)) + 1;
    double sum = 0;
    for (int a = -reach; a <= reach; ++a)
      for (int b = -reach; b <= reach; ++b)
        for (int c = (D == 3 ? -reach : 0); c <= (D == 3 ? reach : 0); ++c) {
          const double r = std::sqrt(double(a * a + b * b + c * c)) * double(dx);
          sum += double(value(T(r)));
        }
    return T(sum);
  }

  // The viscous operator's lattice moment: -dx^D sum_j x_j,0^2 W'(r_j) / (r_j + regularisation)
  // over the same lattice (the neighbour at the origin left out). The laminar viscous term
  // 2 nu sum_j V_j (v_i - v_j) W'(r) / (r + eps) gives the Laplacian of a field exactly where
  // this is 1, as its integral is (for eps = 0); at h = 1.3 dx the lattice gives 0.974 in 2D, so
  // the operator, divided by it, is exact on the lattice as the density summation is.
  T lattice_laplacian_moment(T dx, T regularisation) const {
    const int reach = static_cast<int>(std::ceil(cutoff() / dx)) + 1;
    double sum = 0;
    for (int a = -reach; a <= reach; ++a)
      for (int b = -reach; b <= reach; ++b)
        for (int c = (D == 3 ? -reach : 0); c <= (D == 3 ? reach : 0); ++c) {
          if (a == 0 && b == 0 && c == 0) continue;
          const double r = std::sqrt(double(a * a + b * b + c * c)) * double(dx);
          const double x = double(a) * double(dx);
          sum -= x * x * double(derivative(T(r))) / (r + double(regularisation));
        }
    double volume = 1;
    for (int k = 0; k < D; ++k) volume *= double(dx);
    return T(sum * volume);
  }
};

// dW/dr at a neighbour pair's distance: the pair weight the stored lists cache for the
// pressure and density relaxations (NeighborSearch::for_each_weighted_neighbor; the solver
// fills it at each rebuild, InnerRelation/ContactRelation::update(policy, weight)).
template <class T, int D>
struct PairKernelDerivative {
  WendlandC2Kernel<T, D> kernel;
  template <class Pair>
  UNISPH_HOST_DEVICE T operator()(const Pair& pair) const { return kernel.derivative(pair.distance()); }
};

}  // namespace unisph
