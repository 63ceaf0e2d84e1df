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

#include <algorithm>
#include <cmath>
#include <numbers>
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

// The box that holds every position the material point x0 takes at any time t >= 0, or bounded
// = false where the motion carries it without bound (a constant non-zero speed). From the laws'
// ranges (time_law.hpp: value_range): the rotated offset r(θ) = p + u cos θ + w sin θ (p = n (n·r0),
// u = r0 - p, w = n × r0) is at its extremes per axis at the range's ends and where θ - δ_a is a
// multiple of π (tan δ_a = w_a / u_a), or over the whole circle where the angle may turn by 2π
// or more; the translation adds e [s_lowest, s_highest]. Host only (a table's knots in host memory).
template <int D>
struct SweptBox {
  bool bounded;
  Vecd<D> lower, upper;
};

template <int D>
SweptBox<D> swept_box(const RigidMotion<D>& m, const Vecd<D>& x0) {
  const LawRange s = value_range(m.translation.law);
  if (!s.bounded) return {false, x0, x0};
  SweptBox<D> box{true, x0, x0};
  if (m.rotation.law.kind != TimeLawKind::none) {
    const LawRange theta = value_range(m.rotation.law);
    const Vecd<D> r0 = x0 - m.rotation.pivot;
    Vecd<D> p{}, w{};
    if constexpr (D == 2) {
      w = Vecd<D>{{-r0[1], r0[0]}};
    } else {
      p = m.rotation.axis * dot(m.rotation.axis, r0);
      w = cross(m.rotation.axis, r0);
    }
    const Vecd<D> u = r0 - p;
    const Real pi = std::numbers::pi_v<Real>;
    const bool whole_turn = !theta.bounded || theta.highest - theta.lowest >= Real(2) * pi;
    for (int a = 0; a < D; ++a) {
      const Real radius = std::sqrt(u[a] * u[a] + w[a] * w[a]);
      Real lo, hi;
      if (whole_turn) {
        lo = -radius, hi = radius;
      } else {
        const auto at = [&](Real angle) { return u[a] * std::cos(angle) + w[a] * std::sin(angle); };
        lo = std::min(at(theta.lowest), at(theta.highest));
        hi = std::max(at(theta.lowest), at(theta.highest));
        if (radius > Real(0)) {
          const Real delta = std::atan2(w[a], u[a]);  // u_a cos θ + w_a sin θ = radius cos(θ - δ)
          for (Real k = std::ceil((theta.lowest - delta) / pi); delta + k * pi <= theta.highest; k += Real(1)) {
            const Real v = at(delta + k * pi);
            lo = std::min(lo, v), hi = std::max(hi, v);
          }
        }
      }
      box.lower[a] = m.rotation.pivot[a] + p[a] + lo;
      box.upper[a] = m.rotation.pivot[a] + p[a] + hi;
    }
  }
  for (int a = 0; a < D; ++a) {
    const Real e = m.translation.direction[a];
    box.lower[a] += std::min(e * s.lowest, e * s.highest);
    box.upper[a] += std::max(e * s.lowest, e * s.highest);
  }
  return box;
}

}  // namespace unisph
