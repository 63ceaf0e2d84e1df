#pragma once
// The pieces of the generalized winding number (Jacobson et al. 2013): the signed solid angle
// a triangle subtends at a point (3D) and the signed angle a segment subtends (2D). Summed over
// a closed, outward-oriented surface they give 4π (2π) inside and 0 outside; over an open one
// they vary smoothly, so the winding number is an inside/outside test that degrades gracefully.
// Host and device.

#include <cmath>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"

namespace unisph {

// Signed solid angle of triangle (a, b, c) seen from p (Van Oosterom & Strackee 1983);
// positive where p is behind the triangle's counter-clockwise normal, in (-2π, 2π].
template <class T>
UNISPH_HOST_DEVICE T solid_angle(const Vec<T, 3>& p, const Vec<T, 3>& a, const Vec<T, 3>& b, const Vec<T, 3>& c) {
  const Vec<T, 3> x = a - p, y = b - p, z = c - p;
  const T lx = norm(x), ly = norm(y), lz = norm(z);
  const T numerator = dot(x, cross(y, z));
  const T denominator = lx * ly * lz + dot(x, y) * lz + dot(y, z) * lx + dot(z, x) * ly;
  return T(2) * std::atan2(numerator, denominator);
}

// Signed angle of segment (a, b) seen from p, positive where the segment runs counter-clockwise around p.
template <class T>
UNISPH_HOST_DEVICE T subtended_angle(const Vec<T, 2>& p, const Vec<T, 2>& a, const Vec<T, 2>& b) {
  const Vec<T, 2> x = a - p, y = b - p;
  return std::atan2(cross(x, y), dot(x, y));
}

template <class T>
UNISPH_HOST_DEVICE constexpr T pi() {
  return T(3.14159265358979323846264338327950288);
}

}  // namespace unisph
