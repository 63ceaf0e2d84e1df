#pragma once
// The density-diffusion term of delta-SPH in the continuity equation (Molteni & Colagrossi 2009,
// with the hydrostatic part taken out as Fourtakas et al. 2019 and DualSPHysics do):
//
//   D_i = delta h c0 sum_j 2 [(rho_j - rho_i) - (rho_j^H - rho_i^H)] (-dW_ij / r_ij) V_j
//
// over the fluid neighbours (no wall term: the dummy particles carry no density of their own).
// With the linear equation of state p = c0^2 (rho - rho0), rho_j - rho_i = (p_j - p_i) / c0^2,
// and the hydrostatic density difference is rho0 g . (x_j - x_i) / c0^2, so that
//
//   D_i = (2 delta h / c0) sum_j [p_j - p_i + rho0 g . r_ij] (-dW_ij / r_ij) V_j,  r_ij = x_i - x_j:
//
// the pair reads the p_j the relaxations read anyway (neighbor_records.hpp), nothing more.
// Water at rest in hydrostatic balance makes every bracket zero, so the term does not compress
// it (without the hydrostatic part the term smooths the hydrostatic density gradient away and
// the water sinks next to the free surface). It is linear in the density differences and acts
// at any amplitude, where the Riemann dissipation of the pressure relaxation acts on
// approaching pairs only.
//
// It replaces the Riemann velocity dissipation of the continuity equation, (p_i - p_j)/(rho0 c0)
// (fluid.continuity_dissipation), which is a density diffusion too, about four times as strong
// as this term at delta = 0.1 and without its hydrostatic part: with the density from the
// continuity equation alone that one blew up the 3D dam break (docs/sph.md, "Density"), and the
// two together blew up the 2D one, so a case takes one of them.
#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/neighbor/neighbor_pair.hpp"

namespace unisph::sph {

template <class T, int D>
struct DensityDiffusion {
  T coefficient = T(0);               // 2 delta h / c0; zero: off
  Vec<T, D> hydrostatic_gradient{};   // rho0 g: the hydrostatic pressure gradient

  static DensityDiffusion make(T delta, T smoothing_length, T sound_speed, T reference_density,
                               const Vec<T, D>& gravity) {
    return {T(2) * delta * smoothing_length / sound_speed, gravity * reference_density};
  }
  UNISPH_HOST_DEVICE bool on() const { return coefficient != T(0); }

  // The pair's share of D_i / coefficient, for the kernel derivative dW = dW/dr (<= 0).
  UNISPH_HOST_DEVICE T pair_term(T p_i, T p_j, const NeighborPair<T, D>& pair, T dW, T volume_j) const {
    const T r = pair.distance();
    if (!(r > T(0))) return T(0);
    return (p_j - p_i + dot(hydrostatic_gradient, pair.r_ij)) * (-dW / r) * volume_j;
  }
};

}  // namespace unisph::sph
