// Rigid motions evaluated in kernels on every policy, 2D and 3D: translation, rotation about
// an axis through a pivot, both at once; positions, velocities and accelerations against the
// analytic motion and against finite differences of the positions; bad vectors.
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/motion/rigid_motion.hpp"

namespace {
using namespace unisph;

constexpr Real eps = std::numeric_limits<Real>::epsilon();
const Real pi = std::numbers::pi_v<Real>;

template <int D>
struct MotionKernel {
  RigidMotion<D> motion;
  View<const Vecd<D>> points;
  View<const Real> times;
  View<PointMotion<D>> out;
  UNISPH_HOST_DEVICE void operator()(Index i) const { out[i] = motion(points[i], times[i]); }
};

template <int D>
struct RotateKernel {
  RigidMotion<D> motion;
  View<const Vecd<D>> directions;
  View<const Real> times;
  View<Vecd<D>> out;
  UNISPH_HOST_DEVICE void operator()(Index i) const { out[i] = motion.rotate(directions[i], times[i]); }
};

// motion(points[i], times[i]) in a kernel on the policy.
template <class P, int D>
std::vector<PointMotion<D>> evaluate(P policy, const RigidMotion<D>& motion, const std::vector<Vecd<D>>& points,
                                     const std::vector<Real>& times) {
  DiscreteVariable<Vecd<D>> x("Points");
  x.assign(points);
  DiscreteVariable<Real> t("Times");
  t.assign(times);
  DiscreteVariable<PointMotion<D>> out("PointMotions", points.size());
  particle_for(policy, points.size(), MotionKernel<D>{motion, x.read(policy), t.read(policy), out.write(policy)});
  return out.to_vector();
}

template <int D>
void expect_near(const Vecd<D>& got, const Vecd<D>& expected, Real tolerance, const std::string& what) {
  for (int k = 0; k < D; ++k) EXPECT_NEAR(got[k], expected[k], tolerance) << what << ", component " << k;
}

// Every point at every time, and the central differences of position and velocity over ±h
// against velocity and acceleration.
template <class P, int D>
void expect_derivatives_of_positions(P policy, const RigidMotion<D>& motion, const std::vector<Vecd<D>>& points,
                                     const std::vector<Real>& times, Real h, Real velocity_scale,
                                     Real acceleration_scale) {
  std::vector<Vecd<D>> x;
  std::vector<Real> t;
  for (const Vecd<D>& p : points)
    for (Real time : times)
      for (Real shift : {Real(0), -h, h}) {
        x.push_back(p);
        t.push_back(time + shift);
      }
  const std::vector<PointMotion<D>> m = evaluate(policy, motion, x, t);
  const Real tolerance = 400 * std::cbrt(eps * eps);
  for (std::size_t i = 0; i < m.size(); i += 3) {
    const PointMotion<D>& at = m[i];
    const PointMotion<D>& minus = m[i + 1];
    const PointMotion<D>& plus = m[i + 2];
    const std::string where = "t = " + std::to_string(t[i]);
    expect_near<D>((plus.position - minus.position) / (2 * h), at.velocity, tolerance * velocity_scale, where);
    expect_near<D>((plus.velocity - minus.velocity) / (2 * h), at.acceleration, tolerance * acceleration_scale, where);
  }
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

UNISPH_POLICY_TEST_SUITE(RigidMotionTest);

TYPED_TEST(RigidMotionTest, FixedBodyStaysPut) {
  const std::vector<Vec3d> points = {{{0.1, 0.2, 0.3}}, {{-1, 5, 2}}};
  const std::vector<PointMotion<3>> m = evaluate(this->policy, fixed_motion<3>(), points, {Real(0), Real(7.5)});
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(m[i].position, points[i]);
    EXPECT_EQ(m[i].velocity, Vec3d::zero());
    EXPECT_EQ(m[i].acceleration, Vec3d::zero());
  }
}

TYPED_TEST(RigidMotionTest, TranslationAtConstantVelocity) {
  // Along (3, 4) at 0.5: e = (0.6, 0.8), x = x0 + 0.5 t e.
  const RigidMotion<2> motion = rigid_motion(make_translation(Vec2d{{3, 4}}, constant_rate_law(Real(0.5))));
  EXPECT_NEAR(motion.translation.direction[0], Real(0.6), eps);
  EXPECT_NEAR(motion.translation.direction[1], Real(0.8), eps);
  const std::vector<Vec2d> points = {{{0, 0}}, {{1.5, -2}}, {{0.25, 0.75}}};
  const std::vector<Real> times = {Real(0), Real(0.4), Real(3)};
  const std::vector<PointMotion<2>> m = evaluate(this->policy, motion, points, times);
  const Vec2d e = motion.translation.direction;
  for (std::size_t i = 0; i < points.size(); ++i) {
    expect_near<2>(m[i].position, points[i] + e * (Real(0.5) * times[i]), 4 * eps * (1 + times[i]), "position");
    EXPECT_EQ(m[i].velocity, e * Real(0.5));
    EXPECT_EQ(m[i].acceleration, Vec2d::zero());
  }
}

TYPED_TEST(RigidMotionTest, FlapHingedAtTheFloor2D) {
  // A flap paddle: hinge at (1, 0), the paddle up the y axis, θ = ramped sinusoid; a point at
  // height z on it is at (1 - z sin θ, z cos θ).
  const Real amplitude = Real(0.12), period = Real(1.5);
  const RigidMotion<2> motion =
      rigid_motion(make_rotation(Vec2d{{1, 0}}, sinusoid_law(amplitude, period, Real(0), Real(2))));
  std::vector<Vec2d> points;
  std::vector<Real> times;
  for (Real z : {Real(0), Real(0.3), Real(0.6), Real(1)})
    for (int j = 0; j < 30; ++j) {
      points.push_back(Vec2d{{1, z}});
      times.push_back(Real(0.17) * Real(j));
    }
  const std::vector<PointMotion<2>> m = evaluate(this->policy, motion, points, times);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const LawState theta = motion.rotation.law(times[i]);
    const Real z = points[i][1], s = std::sin(theta.value), c = std::cos(theta.value);
    const Vec2d position{{1 - z * s, z * c}};
    const Vec2d velocity{{-z * c * theta.rate, -z * s * theta.rate}};
    const Vec2d acceleration{{-z * c * theta.acceleration + z * s * theta.rate * theta.rate,
                              -z * s * theta.acceleration - z * c * theta.rate * theta.rate}};
    const Real omega = 2 * pi / period;
    const std::string where = "z = " + std::to_string(z) + ", t = " + std::to_string(times[i]);
    expect_near<2>(m[i].position, position, 16 * eps, where);
    expect_near<2>(m[i].velocity, velocity, 16 * eps * amplitude * omega, where);
    expect_near<2>(m[i].acceleration, acceleration, 16 * eps * amplitude * omega * omega, where);
  }
  // The hinge does not move.
  for (std::size_t i = 0; i < 30; ++i) {
    expect_near<2>(m[i].position, Vec2d{{1, 0}}, 0, "hinge");
    EXPECT_EQ(m[i].velocity, Vec2d::zero());
  }
  const Real omega = 2 * pi / period;
  expect_derivatives_of_positions(this->policy, motion, {Vec2d{{1, 1}}, Vec2d{{1.2, 0.4}}},
                                  {Real(0.5), Real(1.7), Real(3.1), Real(4.4)}, std::cbrt(eps) * period,
                                  amplitude * omega, amplitude * omega * omega + amplitude * amplitude * omega * omega);
}

TYPED_TEST(RigidMotionTest, SwayAndRollAtOnce3D) {
  // A tank that sways along (1, 0, 0.5) and rolls about an oblique axis through its centre,
  // which travels with the sway.
  const Real sway = Real(0.05), sway_period = Real(1.1), roll_rate = Real(0.8);
  const Vec3d pivot{{0.2, -0.1, 0.3}}, axis{{1, 1, 1}};
  const RigidMotion<3> motion =
      rigid_motion(make_translation(Vec3d{{1, 0, 0.5}}, sinusoid_law(sway, sway_period, Real(0.3), Real(1))),
                   make_rotation(pivot, axis, constant_rate_law(roll_rate)));
  const Vec3d n = axis / std::sqrt(Real(3));
  const Vec3d e = Vec3d{{1, 0, 0.5}} / std::sqrt(Real(1.25));
  const std::vector<Vec3d> corners = {{{0, 0, 0}}, {{1, 0, 0}}, {{0.5, 0.7, -0.2}}, {{-0.4, 0.3, 0.9}}};
  std::vector<Vec3d> points;
  std::vector<Real> times;
  for (const Vec3d& p : corners)
    for (int j = 0; j < 12; ++j) {
      points.push_back(p);
      times.push_back(Real(0.37) * Real(j));
    }
  const std::vector<PointMotion<3>> m = evaluate(this->policy, motion, points, times);
  for (std::size_t i = 0; i < points.size(); ++i) {
    // The rotation matrix written as I + sin θ K + (1 - cos θ) K², K the cross-product matrix of n.
    const Real theta = roll_rate * times[i];
    const Mat3d k{{{{0, -n[2], n[1]}}, {{n[2], 0, -n[0]}}, {{-n[1], n[0], 0}}}};
    const Mat3d rotation = Mat3d::identity() + k * std::sin(theta) + (k * k) * (1 - std::cos(theta));
    const LawState s = motion.translation.law(times[i]);
    const Vec3d r = rotation * (points[i] - pivot);
    const Vec3d position = pivot + r + e * s.value;
    const Vec3d velocity = e * s.rate + (k * r) * roll_rate;
    const Vec3d acceleration = e * s.acceleration + (k * (k * r)) * (roll_rate * roll_rate);
    const std::string where = "point " + std::to_string(i / 12) + ", t = " + std::to_string(times[i]);
    expect_near<3>(m[i].position, position, 32 * eps, where);
    expect_near<3>(m[i].velocity, velocity, 32 * eps, where);
    expect_near<3>(m[i].acceleration, acceleration, 32 * eps, where);
    // A rigid motion: the distance to the (moving) axis and the position along it are kept.
    const Vec3d from_pivot = m[i].position - pivot - e * s.value;
    EXPECT_NEAR(norm(cross(from_pivot, n)), norm(cross(points[i] - pivot, n)), 32 * eps) << where;
    EXPECT_NEAR(dot(from_pivot, n), dot(points[i] - pivot, n), 32 * eps) << where;
  }
  const Real omega = 2 * pi / sway_period;
  expect_derivatives_of_positions(this->policy, motion, corners, {Real(0.4), Real(1.3), Real(2.9)},
                                  std::cbrt(eps) * sway_period, sway * omega + roll_rate,
                                  sway * omega * omega + roll_rate * roll_rate);
}

TYPED_TEST(RigidMotionTest, RotationAboutZIsThe2DRotation) {
  const TimeLaw law = sinusoid_law(Real(0.3), Real(2), Real(0.2), Real(0.5));
  const RigidMotion<2> flat = rigid_motion(make_rotation(Vec2d{{0.5, -0.25}}, law));
  const RigidMotion<3> solid = rigid_motion(make_rotation(Vec3d{{0.5, -0.25, 7}}, Vec3d{{0, 0, 2}}, law));
  const std::vector<Vec2d> p2 = {{{1, 1}}, {{-0.3, 0.8}}, {{2, -1}}};
  const std::vector<Vec3d> p3 = {{{1, 1, 0.5}}, {{-0.3, 0.8, -2}}, {{2, -1, 7}}};
  const std::vector<Real> times = {Real(0.3), Real(1.1), Real(2.9)};
  const std::vector<PointMotion<2>> a = evaluate(this->policy, flat, p2, times);
  const std::vector<PointMotion<3>> b = evaluate(this->policy, solid, p3, times);
  for (std::size_t i = 0; i < p2.size(); ++i) {
    for (int k = 0; k < 2; ++k) {
      EXPECT_NEAR(a[i].position[k], b[i].position[k], 8 * eps * 4);
      EXPECT_NEAR(a[i].velocity[k], b[i].velocity[k], 8 * eps * 4);
      EXPECT_NEAR(a[i].acceleration[k], b[i].acceleration[k], 8 * eps * 8);
    }
    EXPECT_NEAR(b[i].position[2], p3[i][2], 8 * eps * 8);
    EXPECT_NEAR(b[i].velocity[2], Real(0), 8 * eps);
  }
}

TYPED_TEST(RigidMotionTest, RotateTurnsDirectionsAsTheBodyTurns) {
  const RigidMotion<3> motion = rigid_motion(make_translation(Vec3d{{0, 1, 0}}, constant_rate_law(Real(2))),
                                             make_rotation(Vec3d{{1, 2, 3}}, Vec3d{{0, 1, 1}}, constant_rate_law(Real(1.3))));
  const std::vector<Vec3d> directions = {{{1, 0, 0}}, {{0, 1, 0}}, {{0, 0, 1}}, {{0.6, 0, 0.8}}};
  const std::vector<Real> times = {Real(0.5), Real(0.5), Real(0.5), Real(2.25)};
  DiscreteVariable<Vec3d> d("Directions");
  d.assign(directions);
  DiscreteVariable<Real> t("Times");
  t.assign(times);
  DiscreteVariable<Vec3d> out("Turned", directions.size());
  particle_for(this->policy, directions.size(), RotateKernel<3>{motion, d.read(this->policy), t.read(this->policy), out.write(this->policy)});
  const std::vector<Vec3d> turned = out.to_vector();
  // R v = x(p + v) - x(p) for any material point p.
  const Vec3d p{{0.3, -0.2, 0.1}};
  for (std::size_t i = 0; i < directions.size(); ++i) {
    const Vec3d expected = motion.position(p + directions[i], times[i]) - motion.position(p, times[i]);
    expect_near<3>(turned[i], expected, 32 * eps * 8, "direction " + std::to_string(i));
    EXPECT_NEAR(norm(turned[i]), Real(1), 8 * eps);
  }
  // The first three stay orthonormal.
  EXPECT_NEAR(dot(turned[0], turned[1]), Real(0), 8 * eps);
  EXPECT_NEAR(dot(cross(turned[0], turned[1]), turned[2]), Real(1), 8 * eps);
}

TEST(HostRigidMotion, BadVectorsAreOneLineErrors) {
  EXPECT_EQ(error_of([] { make_rotation(Vec3d{{0, 0, 0}}, Vec3d{{0, 0, 0}}, no_motion()); }),
            "rotation: the axis (0, 0, 0) has zero length (or is not finite)");
  EXPECT_EQ(error_of([] { make_rotation(Vec3d{{0, 0, 0}}, Vec3d{{0, 0, 0}}, no_motion(), "flap.axis"); }),
            "flap.axis: the axis (0, 0, 0) has zero length (or is not finite)");
  EXPECT_EQ(error_of([] { make_translation(Vec2d{{0, 0}}, no_motion()); }),
            "translation: the direction (0, 0) has zero length (or is not finite)");
  EXPECT_EQ(error_of([] {
              make_translation(Vec3d{{1, std::numeric_limits<Real>::infinity(), 0}}, no_motion(), "tank.direction");
            }),
            "tank.direction: the direction (1, inf, 0) has zero length (or is not finite)");
  EXPECT_EQ(error_of([] { make_rotation(Vec2d{{std::numeric_limits<Real>::quiet_NaN(), 0}}, no_motion()); }),
            "rotation: the pivot must be finite");
}

}  // namespace

// swept_box holds every position a point takes at t >= 0 and is tight (the samples reach its
// faces): a flap turning ±12° about its hinge (2D), a tank that sways and rolls about a skew axis
// (3D, a rotation of ±50° and a translation: the box adds the two ranges, which the path need not
// reach at once, so it holds the path without touching it; the roll alone is tight), a plate turning by more than a whole turn (its
// circle), a piston; a constant speed sweeps no bounded box.
template <int D>
void expect_swept_box_holds_the_path(const RigidMotion<D>& m, const Vecd<D>& x0, Real until, const char* what,
                                     bool tight = true) {
  const SweptBox<D> box = swept_box(m, x0);
  ASSERT_TRUE(box.bounded) << what;
  Vecd<D> lowest = m.position(x0, Real(0)), highest = lowest;
  const int samples = 100000;
  for (int i = 0; i <= samples; ++i) {
    const Vecd<D> x = m.position(x0, until * Real(i) / samples);
    for (int a = 0; a < D; ++a) {
      EXPECT_GE(x[a], box.lower[a] - 64 * eps) << what << ", axis " << a << ", sample " << i;
      EXPECT_LE(x[a], box.upper[a] + 64 * eps) << what << ", axis " << a << ", sample " << i;
      lowest[a] = std::min(lowest[a], x[a]), highest[a] = std::max(highest[a], x[a]);
    }
  }
  for (int a = 0; a < D && tight; ++a) {
    EXPECT_NEAR(lowest[a], box.lower[a], 1e-6) << what << ", axis " << a;
    EXPECT_NEAR(highest[a], box.upper[a], 1e-6) << what << ", axis " << a;
  }
}

TEST(HostRigidMotion, SweptBoxHoldsEveryPositionAndIsTight) {
  const Real degree = pi / 180;
  const RigidMotion<2> flap = rigid_motion<2>(make_rotation(Vec2d{{0, -0.1}}, sinusoid_law(12 * degree, Real(4.5), 0, 2)));
  expect_swept_box_holds_the_path<2>(flap, Vec2d{{-0.05, 1.4}}, Real(30), "flap, top");
  expect_swept_box_holds_the_path<2>(flap, Vec2d{{0.0, 0.2}}, Real(30), "flap, near the hinge");
  const RigidMotion<2> piston = rigid_motion<2>(make_translation(Vec2d{{1, 0}}, sinusoid_law(Real(0.05), Real(7.2), 0, 2)));
  expect_swept_box_holds_the_path<2>(piston, Vec2d{{-0.1, 0.7}}, Real(40), "piston");
  const RigidMotion<2> spinning = rigid_motion<2>(make_rotation(Vec2d{{1, 1}}, sinusoid_law(Real(4), Real(3))));
  expect_swept_box_holds_the_path<2>(spinning, Vec2d{{1.5, 0.2}}, Real(12), "more than a whole turn");
  const RigidMotion<3> tank = rigid_motion<3>(make_translation(Vec3d{{1, 0.5, 0}}, sinusoid_law(Real(0.3), Real(2), 0, 1)),
                                              make_rotation(Vec3d{{0.5, 0.5, 0.2}}, Vec3d{{0.3, 1, 0.2}},
                                                            sinusoid_law(50 * degree, Real(3.3), Real(0.4))));
  expect_swept_box_holds_the_path<3>(tank, Vec3d{{1.0, 0.1, 0.9}}, Real(66), "sway and roll", false);
  expect_swept_box_holds_the_path<3>(rigid_motion<3>(tank.rotation), Vec3d{{1.0, 0.1, 0.9}}, Real(66), "roll");
  EXPECT_FALSE(swept_box(rigid_motion<2>(make_translation(Vec2d{{0, 1}}, constant_rate_law(Real(0.5)))), Vec2d{{0, 0}}).bounded);
}
