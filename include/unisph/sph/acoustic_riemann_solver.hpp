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
#include <cmath>

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

  // fmax/fmin rather than conditionals: the sign of the jump is unpredictable pair by pair, and
  // the branches the compiler made of the conditionals cost 13 % of a dam-break run (measured).
  // The values are the same, NaN included (both forms give 0 and then 1 for a NaN jump).
  UNISPH_HOST_DEVICE T limiter(T velocity_jump) const {
    const T approach = std::fmax(velocity_jump, T(0));
    return std::fmin(T(3) * approach * inverse_sound_speed, T(1));
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
