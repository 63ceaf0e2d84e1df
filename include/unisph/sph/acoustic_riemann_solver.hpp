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

#if !UNISPH_DEVICE_CODE && defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace unisph::sph {

template <class T>
struct AcousticRiemannSolver {
  T impedance = T(1);          // rho0 c0
  T inverse_impedance = T(1);  // 1 / (rho0 c0)
  T inverse_sound_speed = T(1);

  static AcousticRiemannSolver make(T reference_density, T sound_speed) {
    return {reference_density * sound_speed, T(1) / (reference_density * sound_speed), T(1) / sound_speed};
  }

  // No branch on the sign of the jump: it is unpredictable pair by pair (the branches the
  // compiler made of conditionals cost 13 % of a dam-break run, measured). The device takes
  // fmax/fmin (single instructions there). On the x86-64 host, GCC calls libm's fmax/fmin out of
  // line (without -ffinite-math-only), and the calls make it spill the pair loop's values to
  // the stack, while plain selects become branches again; the SSE max/min instructions below
  // are neither, and give the bits glibc's fmax(x, y) = x > y ? x : y and fmin(x, y) =
  // x < y ? x : y give, NaN included (a NaN jump gives approach 0; fmin's argument is never
  // NaN). Measured on the 2D dam break, seq, t = 0..3: the pressure relaxation pass was 43 % of
  // the samples with 4 % more in fmax/fmin (docs/sph.md, performance).
  UNISPH_HOST_DEVICE T limiter(T velocity_jump) const {
#if UNISPH_DEVICE_CODE || !defined(__SSE2__)
    const T approach = std::fmax(velocity_jump, T(0));
    return std::fmin(T(3) * approach * inverse_sound_speed, T(1));
#else
    const T approach = host_max(velocity_jump, T(0));
    return host_min(T(3) * approach * inverse_sound_speed, T(1));
#endif
  }
#if !UNISPH_DEVICE_CODE && defined(__SSE2__)
  // x > y ? x : y and x < y ? x : y (y when unordered), without a branch.
  static T host_max(T x, T y) {
    if constexpr (sizeof(T) == 8) return _mm_cvtsd_f64(_mm_max_sd(_mm_set_sd(x), _mm_set_sd(y)));
    else return _mm_cvtss_f32(_mm_max_ss(_mm_set_ss(x), _mm_set_ss(y)));
  }
  static T host_min(T x, T y) {
    if constexpr (sizeof(T) == 8) return _mm_cvtsd_f64(_mm_min_sd(_mm_set_sd(x), _mm_set_sd(y)));
    else return _mm_cvtss_f32(_mm_min_ss(_mm_set_ss(x), _mm_set_ss(y)));
  }
#endif
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
