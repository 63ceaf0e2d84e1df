#pragma once
// Linear (first-order) water-wave theory for wave makers and wave flumes, host and device:
//
//   dispersion        ω² = g k tanh(k d), solved for k to machine precision
//   wave makers       Biésel's transfer functions H/S of a piston and of a flap hinged at the
//                     floor, and from them the stroke S that makes a wave of height H
//   reflection        the incident and reflected waves from two gauges (Goda & Suzuki 1976)
//
// The functions are templates over the floating-point type (float, double) and UNISPH_HOST_DEVICE;
// invalid arguments give NaN (they cannot throw on the device). The analysis of measured time
// series (a least-squares sinusoid fit and the two-gauge method on series) is host code in
// wave_analysis.hpp. docs/motion.md writes out the formulas and their sources.

#include <cmath>
#include <limits>
#include <numbers>

#include "unisph/core/config.hpp"

namespace unisph {

// The wave number k (rad/m) of a linear wave of angular frequency ω in water of depth d under
// gravity g: the root of ω² = g k tanh(k d). Written as x tanh x = y with x = k d and
// y = ω² d / g; the start is Fenton & McKee's explicit approximation (Coastal Engineering 14,
// 1990), x0 = y coth(y^(3/4))^(2/3), within 0.1 % everywhere, then Newton's method until a step
// changes x by at most one unit of round-off (two or three steps). An infinite depth gives the
// deep-water k = ω²/g; ω = 0 gives 0; ω < 0, d <= 0 or g <= 0 give NaN.
template <class T>
UNISPH_HOST_DEVICE T wave_number(T omega, T depth, T g) {
  if (!(omega >= T(0)) || !(depth > T(0)) || !(g > T(0))) return std::numeric_limits<T>::quiet_NaN();
  if (omega == T(0)) return T(0);
  const T k_deep = omega * omega / g;
  const T y = k_deep * depth;
  if (!(y < std::numeric_limits<T>::infinity())) return k_deep;  // infinite depth
  T x = y / std::pow(std::tanh(std::pow(y, T(0.75))), T(2) / T(3));
  for (int iteration = 0; iteration < 50; ++iteration) {
    const T th = std::tanh(x), ch = std::cosh(x);
    const T step = (x * th - y) / (th + x / (ch * ch));
    x -= step;
    if (!(std::abs(step) > std::numeric_limits<T>::epsilon() * x)) break;
  }
  return x / depth;
}

// The same for a period T = 2π/ω.
template <class T>
UNISPH_HOST_DEVICE T wave_number_for_period(T period, T depth, T g) {
  return wave_number(T(2) * std::numbers::pi_v<T> / period, depth, g);
}

// The wave length L = 2π / k for a period.
template <class T>
UNISPH_HOST_DEVICE T wave_length(T period, T depth, T g) {
  return T(2) * std::numbers::pi_v<T> / wave_number_for_period(period, depth, g);
}

// The angular frequency of the wave number k: ω = sqrt(g k tanh(k d)) (the dispersion relation
// read forwards).
template <class T>
UNISPH_HOST_DEVICE T dispersion_frequency(T k, T depth, T g) {
  return std::sqrt(g * k * std::tanh(k * depth));
}

// Biésel's first-order transfer function of a piston wave maker: the ratio of the wave height H
// far from the paddle to the paddle's stroke S (twice its amplitude), as a function of k d
// (Biésel & Suquet 1951; in the form of Dean & Dalrymple, Water Wave Mechanics for Engineers
// and Scientists, 1991, wavemaker theory):
//   H/S = 2 (cosh 2kd - 1) / (sinh 2kd + 2kd) = 4 sinh² kd / (sinh 2kd + 2kd)
// → kd in shallow water (H/S = kd (1 - (kd)⁴/45 + ...)), → 2 in deep water. Evaluated with
// q = e^(-2kd), m = 1 - q (expm1) as 2 m² / (m (2 - m) + 4 kd q), which neither cancels for small
// kd nor overflows for large kd.
template <class T>
UNISPH_HOST_DEVICE T piston_height_to_stroke(T kd) {
  if (!(kd >= T(0))) return std::numeric_limits<T>::quiet_NaN();
  if (kd == T(0)) return T(0);
  const T m = -std::expm1(T(-2) * kd);
  return T(2) * m * m / (m * (T(2) - m) + T(4) * kd * (T(1) - m));
}

// The same for a flap hinged at the floor, S being the stroke at the still-water level
// (Dean & Dalrymple's form):
//   H/S = 4 (sinh kd / kd) (kd sinh kd - cosh kd + 1) / (sinh 2kd + 2kd)
// → kd/2 in shallow water, → 2 (slowly: 2 (1 - 1/kd) for large kd) in deep water. For kd <= 1
// with cosh kd - 1 = 2 sinh²(kd/2); above, scaled by e^(-2kd) (q = e^(-2kd)) as
//   2 (1 - q) (kd (1 - q) - (1 + q) + 2 e^(-kd)) / (kd (1 - q² + 4 kd q)).
template <class T>
UNISPH_HOST_DEVICE T flap_height_to_stroke(T kd) {
  if (!(kd >= T(0))) return std::numeric_limits<T>::quiet_NaN();
  if (kd == T(0)) return T(0);
  if (kd <= T(1)) {
    const T s = std::sinh(kd), half = std::sinh(kd / T(2));
    return T(4) * (s / kd) * (kd * s - T(2) * half * half) / (std::sinh(T(2) * kd) + T(2) * kd);
  }
  const T q = std::exp(T(-2) * kd);
  return T(2) * (T(1) - q) * (kd * (T(1) - q) - (T(1) + q) + T(2) * std::exp(-kd)) /
         (kd * (T(1) - q * q + T(4) * kd * q));
}

// The piston stroke S (twice the paddle's amplitude) for a wave of height H and period T in
// water of depth d: S = H / (H/S)(k d).
template <class T>
UNISPH_HOST_DEVICE T piston_stroke(T height, T period, T depth, T g) {
  return height / piston_height_to_stroke(wave_number_for_period(period, depth, g) * depth);
}

// The flap's stroke at the still-water level for a wave of height H and period T, the hinge on
// the floor at depth d.
template <class T>
UNISPH_HOST_DEVICE T flap_stroke(T height, T period, T depth, T g) {
  return height / flap_height_to_stroke(wave_number_for_period(period, depth, g) * depth);
}

// The angle amplitude (radians) of a flap hinged `hinge_depth` below the still-water level whose
// line crosses the still-water level S/2 from its rest position: atan(S / (2 d_h)). To first
// order S / (2 d_h), the linear theory's flap.
template <class T>
UNISPH_HOST_DEVICE T flap_angle_amplitude(T stroke, T hinge_depth) {
  return std::atan(stroke / (T(2) * hinge_depth));
}

// Incident and reflected linear waves at one frequency, with gauge 1 at x1 and gauge 2 at
// x1 + Δ (Δ > 0 in the incident wave's direction). At gauge 1,
//   η(x1, t) = a_I sin(ω t + φ_I) + a_R sin(ω t + φ_R),
// the incident wave travelling towards +x (η_I(x, t) = a_I sin(ω t - k (x - x1) + φ_I)) and the
// reflected one towards -x (η_R = a_R sin(ω t + k (x - x1) + φ_R)).
template <class T>
struct IncidentReflected {
  T incident_amplitude;      // a_I
  T incident_phase;          // φ_I (radians, at gauge 1)
  T reflected_amplitude;     // a_R
  T reflected_phase;         // φ_R (radians, at gauge 1)
  T reflection_coefficient;  // a_R / a_I
};

// Goda & Suzuki's (1976) separation at one frequency from the gauges' cosine and sine
// coefficients, η_j(t) = A_j cos ω t + B_j sin ω t (j = 1, 2), for the wave number k and the
// gauge spacing Δ. With complex amplitudes Z_j = A_j + i B_j (η = Re[Z e^(-iωt)]):
//   Z_1 = I + R,  Z_2 = I e^(ikΔ) + R e^(-ikΔ)
//   I = (Z_2 - Z_1 e^(-ikΔ)) / (2i sin kΔ),  R = (Z_1 e^(ikΔ) - Z_2) / (2i sin kΔ)
// which are Goda & Suzuki's a_I, a_R; a phase is atan2(Re, Im) of its amplitude. Singular where
// sin kΔ = 0 (Δ a multiple of half a wave length): Goda & Suzuki keep 0.05 < Δ/L < 0.45.
template <class T>
UNISPH_HOST_DEVICE IncidentReflected<T> separate_incident_reflected(T a1, T b1, T a2, T b2, T k, T spacing) {
  const T c = std::cos(k * spacing), s = std::sin(k * spacing);
  const T denominator = T(2) * s;
  // Z_2 - Z_1 e^(-ikΔ) and Z_1 e^(ikΔ) - Z_2, then divided by 2i sin kΔ: (u + iv) / (2i s) = (v - iu) / (2s).
  const T iu = a2 - (a1 * c + b1 * s), iv = b2 - (b1 * c - a1 * s);
  const T ru = (a1 * c - b1 * s) - a2, rv = (b1 * c + a1 * s) - b2;
  const T i_re = iv / denominator, i_im = -iu / denominator;
  const T r_re = rv / denominator, r_im = -ru / denominator;
  IncidentReflected<T> out{};
  out.incident_amplitude = std::sqrt(i_re * i_re + i_im * i_im);
  out.reflected_amplitude = std::sqrt(r_re * r_re + r_im * r_im);
  out.incident_phase = std::atan2(i_re, i_im);
  out.reflected_phase = std::atan2(r_re, r_im);
  out.reflection_coefficient = out.reflected_amplitude / out.incident_amplitude;
  return out;
}

}  // namespace unisph
