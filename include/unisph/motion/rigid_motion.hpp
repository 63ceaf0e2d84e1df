#pragma once
// Prescribed rigid motion of a body in 2D and 3D: a translation along a fixed direction and a
// rotation about a fixed axis through a pivot, each driven by a TimeLaw (time_law.hpp), alone
// or at once. For a material point at x0 in the body's reference position (both laws at 0):
//
//   r(t) = R(θ(t)) (x0 - c)                          c: the pivot, R: rotation by θ about n
//   x(t) = c + r(t) + e s(t)                         e: the unit direction, s: the displacement
//   v(t) = e s' + θ' n × r
//   a(t) = e s'' + θ'' n × r + θ'² n × (n × r)       (n fixed, so the angular acceleration is θ'' n)
//
// The pivot moves with the translation (a tank that sways and rolls about its centre). In 2D
// the axis is z and θ turns counter-clockwise (x towards y): n × r = (-r_y, r_x),
// n × (n × r) = -r. In 3D, R is Rodrigues' rotation about the unit axis n (right-hand rule).
//
// Everything is exact (no time stepping) and UNISPH_HOST_DEVICE; the values are trivially
// copyable for kernels. The factories (host) check their vectors and throw a one-line Error.

#include <cmath>
#include <string>
#include <string_view>

#include "unisph/core/error.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/motion/time_law.hpp"

namespace unisph {

// A translation x0 -> x0 + e s(t).
template <int D>
struct Translation {
  Vecd<D> direction;  // e, unit length
  TimeLaw law;        // s(t)
};

// A rotation by θ(t) about the axis through the pivot (2D: the z axis; `axis` is unused there).
template <int D>
struct Rotation {
  Vecd<D> pivot;  // c
  Vec3d axis;     // n, unit length (3D)
  TimeLaw law;    // θ(t), radians
};

// Position, velocity and acceleration of one material point.
template <int D>
struct PointMotion {
  Vecd<D> position, velocity, acceleration;
};

template <int D>
struct RigidMotion {
  static_assert(D == 2 || D == 3, "unisph::RigidMotion is for 2D and 3D bodies");
  Translation<D> translation;
  Rotation<D> rotation;

  // R(θ(t)) v: how the body has turned a direction (a wall normal) at time t.
  UNISPH_HOST_DEVICE Vecd<D> rotate(const Vecd<D>& v, Real t) const {
    if (rotation.law.kind == TimeLawKind::none) return v;
    return turned(v, rotation.law(t).value);
  }

  // Where the material point x0 is at time t, and its velocity and acceleration there.
  UNISPH_HOST_DEVICE PointMotion<D> operator()(const Vecd<D>& x0, Real t) const {
    const LawState s = translation.law(t);
    const Vecd<D>& e = translation.direction;
    if (rotation.law.kind == TimeLawKind::none)  // x0 itself, not c + (x0 - c), which rounds
      return {x0 + e * s.value, e * s.rate, e * s.acceleration};
    const LawState theta = rotation.law(t);
    const Vecd<D> r = turned(x0 - rotation.pivot, theta.value);
    const Vecd<D> nr = axis_cross(r);        // n × r
    const Vecd<D> nnr = axis_cross(nr);      // n × (n × r)
    return {rotation.pivot + r + e * s.value, e * s.rate + nr * theta.rate,
            e * s.acceleration + nr * theta.acceleration + nnr * (theta.rate * theta.rate)};
  }
  UNISPH_HOST_DEVICE Vecd<D> position(const Vecd<D>& x0, Real t) const { return (*this)(x0, t).position; }
  UNISPH_HOST_DEVICE Vecd<D> velocity(const Vecd<D>& x0, Real t) const { return (*this)(x0, t).velocity; }
  UNISPH_HOST_DEVICE Vecd<D> acceleration(const Vecd<D>& x0, Real t) const { return (*this)(x0, t).acceleration; }

 private:
  UNISPH_HOST_DEVICE Vecd<D> axis_cross(const Vecd<D>& r) const {
    if constexpr (D == 2) {
      return Vecd<D>{{-r[1], r[0]}};
    } else {
      return cross(rotation.axis, r);
    }
  }
  UNISPH_HOST_DEVICE Vecd<D> turned(const Vecd<D>& r, Real angle) const {
    const Real c = std::cos(angle), s = std::sin(angle);
    if constexpr (D == 2) {
      return Vecd<D>{{c * r[0] - s * r[1], s * r[0] + c * r[1]}};
    } else {
      const Vec3d& n = rotation.axis;
      return r * c + cross(n, r) * s + n * (dot(n, r) * (Real(1) - c));
    }
  }
};

namespace detail {
template <int D>
std::string motion_vector_text(const Vecd<D>& v) {
  std::string s = "(";
  for (int i = 0; i < D; ++i) s += (i ? ", " : "") + law_number(v[i]);
  return s + ")";
}
}  // namespace detail

template <int D>
Translation<D> no_translation() {
  return {Vecd<D>::unit(0), no_motion()};
}
template <int D>
Rotation<D> no_rotation() {
  return {Vecd<D>::zero(), Vec3d::unit(2), no_motion()};
}

// Translation along `direction` (any length but zero; it is normalised) by the law s(t).
template <int D>
Translation<D> make_translation(const Vecd<D>& direction, const TimeLaw& law, std::string_view where = "translation") {
  const Real length = norm(direction);
  if (!(length > Real(0)) || !std::isfinite(length))
    detail::time_law_error(where, "the direction " + detail::motion_vector_text<D>(direction) +
                                      " has zero length (or is not finite)");
  return {direction / length, law};
}

// 2D: rotation by θ(t) (counter-clockwise) about the point `pivot`.
inline Rotation<2> make_rotation(const Vec2d& pivot, const TimeLaw& law, std::string_view where = "rotation") {
  if (!std::isfinite(pivot[0]) || !std::isfinite(pivot[1])) detail::time_law_error(where, "the pivot must be finite");
  return {pivot, Vec3d::unit(2), law};
}
// 3D: rotation by θ(t) about the axis through `pivot` along `axis` (any length but zero).
inline Rotation<3> make_rotation(const Vec3d& pivot, const Vec3d& axis, const TimeLaw& law,
                                 std::string_view where = "rotation") {
  if (!std::isfinite(pivot[0]) || !std::isfinite(pivot[1]) || !std::isfinite(pivot[2]))
    detail::time_law_error(where, "the pivot must be finite");
  const Real length = norm(axis);
  if (!(length > Real(0)) || !std::isfinite(length))
    detail::time_law_error(where, "the axis " + detail::motion_vector_text<3>(axis) + " has zero length (or is not finite)");
  return {pivot, axis / length, law};
}

template <int D>
RigidMotion<D> rigid_motion(const Translation<D>& translation, const Rotation<D>& rotation) {
  return {translation, rotation};
}
template <int D>
RigidMotion<D> rigid_motion(const Translation<D>& translation) {
  return {translation, no_rotation<D>()};
}
template <int D>
RigidMotion<D> rigid_motion(const Rotation<D>& rotation) {
  return {no_translation<D>(), rotation};
}
// A body that does not move.
template <int D>
RigidMotion<D> fixed_motion() {
  return {no_translation<D>(), no_rotation<D>()};
}

}  // namespace unisph
