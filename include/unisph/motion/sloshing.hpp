#pragma once
// Linear sloshing in a rectangular tank of length L (between its walls) and still-water depth
// h, after the linear modal theory of Faltinsen & Timokha (Sloshing, Cambridge University
// Press, 2009): natural frequencies, and the steady free surface under a harmonic sway. Host
// and device; templates over the floating-point type. The derivation of the sway response is
// written out in docs/motion.md.

#include <cmath>
#include <limits>
#include <numbers>

#include "unisph/core/config.hpp"

namespace unisph {

// k_n = n π / L: the wave number of the n-th mode, η_n ∝ cos(k_n (x + L/2)) with x from the
// tank's centre (n = 1: the first antisymmetric mode, half a wave length across the tank).
template <class T>
UNISPH_HOST_DEVICE T sloshing_wave_number(int mode, T length) {
  return T(mode) * std::numbers::pi_v<T> / length;
}

// ω_n = sqrt(g k_n tanh(k_n h)).
template <class T>
UNISPH_HOST_DEVICE T sloshing_natural_frequency(int mode, T length, T depth, T g) {
  const T k = sloshing_wave_number(mode, length);
  return std::sqrt(g * k * std::tanh(k * depth));
}

// T_n = 2π / ω_n.
template <class T>
UNISPH_HOST_DEVICE T sloshing_natural_period(int mode, T length, T depth, T g) {
  return T(2) * std::numbers::pi_v<T> / sloshing_natural_frequency(mode, length, depth, g);
}

// The steady linear free surface of the tank swaying as X(t) = A sin ω t (no damping):
// η(x, t) = E(x) sin ω t, x from the tank's centre in the tank's frame (-L/2 <= x <= L/2),
// positive in the direction of X, where
//   E(x) = (A ω² / g) Σ_{n odd} c_n cos(k_n (x + L/2)) ω_n² / (ω_n² - ω²),   c_n = -4 / (L k_n²)
// (only the odd modes are forced: the even ones are symmetric about the centre). Since
// Σ c_n cos(k_n (x + L/2)) = x on the tank, this is summed as
//   E(x) = (A ω² / g) [x + Σ_{n odd} c_n cos(k_n (x + L/2)) ω² / (ω_n² - ω²)]
// whose terms fall as n^-3: the first `modes` odd modes (n = 1, 3, ..., 2 modes - 1) leave out
// about (A ω² / g) ω² L² / (4 π³ g modes²) at the wall (the deep-water tail; 1.4e-9 m for
// L = 1 m, h = 0.5 m, A = 1 cm at 1.2 times the first natural frequency with 1000 modes). E is infinite at ω = ω_n (n odd); below ω_1, E(L/2) > 0: the water rises on the
// wall towards which the tank is displaced, as the quasi-static tilt -Ẍ x / g (ω → 0) says.
template <class T>
UNISPH_HOST_DEVICE T sway_elevation_amplitude(T x, T length, T depth, T sway_amplitude, T omega, T g,
                                              int modes = 1000) {
  const T omega2 = omega * omega;
  T sum = x;
  for (int j = 0; j < modes; ++j) {
    const int n = 2 * j + 1;
    const T k = sloshing_wave_number(n, length);
    const T natural2 = g * k * std::tanh(k * depth);
    const T c = T(-4) / (length * k * k);
    sum += c * std::cos(k * (x + length / T(2))) * omega2 / (natural2 - omega2);
  }
  return sway_amplitude * omega2 / g * sum;
}

// E at the wall x = +L/2 (cos(k_n L) = -1 for odd n): the amplitude of the elevation on the
// wall towards which the sway displaces the tank (the other wall's is its negative).
template <class T>
UNISPH_HOST_DEVICE T sway_wall_elevation_amplitude(T length, T depth, T sway_amplitude, T omega, T g, int modes = 1000) {
  const T omega2 = omega * omega;
  T sum = length / T(2);
  for (int j = 0; j < modes; ++j) {
    const T k = sloshing_wave_number(2 * j + 1, length);
    const T natural2 = g * k * std::tanh(k * depth);
    sum += T(4) / (length * k * k) * omega2 / (natural2 - omega2);
  }
  return sway_amplitude * omega2 / g * sum;
}

// η(x, t) = E(x) sin ω t.
template <class T>
UNISPH_HOST_DEVICE T sway_elevation(T x, T t, T length, T depth, T sway_amplitude, T omega, T g, int modes = 1000) {
  return sway_elevation_amplitude(x, length, depth, sway_amplitude, omega, g, modes) * std::sin(omega * t);
}

}  // namespace unisph
