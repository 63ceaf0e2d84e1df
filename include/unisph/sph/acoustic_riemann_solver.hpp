#pragma once
// Linearised (acoustic) Riemann solver between two particles, with a dissipation limiter.
//
// Along the line of the pair, the left state is particle i and the right state particle j;
// u_L - u_R = -(v_i - v_j) . e_ij (e_ij points from j to i) is positive when they approach.
// The interface pressure and velocity of the acoustic solver are
//   p* = (p_i + p_j)/2 + beta rho0 c0 (u_L - u_R)/2,    u* = (u_L + u_R)/2 + (p_L - p_R)/(2 rho0 c0).
// The pressure dissipation is what keeps the scheme stable but it also damps the flow; the
// limiter beta = min(3 max(u_L - u_R, 0)/c0, 1) switches it off for separating pairs and
// scales it down for slowly approaching ones, so that a fluid at rest is not damped and a
// violent impact gets the full acoustic impedance. (The idea of the limiter is the one of
// SPHinXsys' dissipation limiter; this is an independent implementation.)
#include "unisph/core/config.hpp"

namespace unisph::sph {

template <class T>
struct AcousticRiemannSolver {
  T impedance = T(1);          // rho0 c0
  T inverse_impedance = T(1);  // 1 / (rho0 c0)
  T inverse_sound_speed = T(1);

  static AcousticRiemannSolver make(T reference_density, T sound_speed) {
    return {reference_density * sound_speed, T(1) / (reference_density * sound_speed), T(1) / sound_speed};
  }

  UNISPH_HOST_DEVICE T limiter(T velocity_jump) const {
    const T approach = velocity_jump > T(0) ? velocity_jump : T(0);
    const T beta = T(3) * approach * inverse_sound_speed;
    return beta < T(1) ? beta : T(1);
  }
  // Twice the interface pressure: p_i + p_j + beta rho0 c0 (u_L - u_R).
  UNISPH_HOST_DEVICE T twice_interface_pressure(T p_left, T p_right, T velocity_jump) const {
    return p_left + p_right + limiter(velocity_jump) * impedance * velocity_jump;
  }
  // The velocity dissipation of the continuity equation: (p_L - p_R) / (rho0 c0).
  UNISPH_HOST_DEVICE T velocity_dissipation(T p_left, T p_right) const {
    return (p_left - p_right) * inverse_impedance;
  }
};

}  // namespace unisph::sph
