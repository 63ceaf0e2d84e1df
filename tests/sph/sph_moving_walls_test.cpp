// Moving walls (issue 22; sph/moving_walls.hpp, [body.translation] / [body.rotation]), on every
// policy:
//  * a piston (translation, ramped sinusoid) and a flap (rotation about its hinge) follow their
//    laws: after every advection step each wall particle's position, normal and velocity equal
//    the analytic law's at the solver's time (to round-off of the law's own arithmetic);
//  * a tank translating at constant velocity U with water moving at U (both from time 0, after a
//    settling stage with the tank held) carries the water as the still tank holds it: the
//    water's velocity relative to the tank equals the still tank's velocity field within
//    1e-3 sqrt(g d) (Galilean invariance); the relative velocity itself is printed beside the
//    still tank's residual motion (water at rest drifts, issue 23);
//  * static walls and walls moving at speed 0 give the same bits (the relaxations' common-case
//    kernel against the general one);
//  * a checkpoint of a run with a moving wall restarts bit for bit (seq);
//  * broken motions are refused with one line naming the file, the line and the key.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "support/by_id.hpp"
#include "support/case_text.hpp"
#include "support/policy_test.hpp"
#include "unisph/solver/case_file.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"

using namespace unisph;
using namespace unisph::sph;
using unisph::testing::by_id;
using unisph::testing::kind_of;
using unisph::testing::replaced;

namespace {

std::string numbers(const std::vector<double>& v) {
  std::ostringstream s;
  s.precision(17);
  s << "[";
  for (std::size_t k = 0; k < v.size(); ++k) s << (k ? ", " : "") << v[k];
  return s.str() + "]";
}

// A 2D tank [0, 1] x [0, 1] of wall 4 dx deep (outer box = inside + 4 dx), water of depth d = 0.5
// started hydrostatic, in a domain [-1, 3] x [-0.5, 1.5] that holds the tank wherever it goes. The
// tank and the water are given by `tank_motion` and `water_velocity`; `extra` adds bodies.
std::string tank_case(double dx, const std::string& tank_motion, const std::vector<double>& water_velocity,
                      const std::string& extra = "", double settling = 0) {
  const double e = 4 * dx;
  std::ostringstream s;
  s.precision(17);
  s << "[case]\nname = \"moving_tank_2d\"\ndimension = 2\n[geometry]\ndx = " << dx << "\n"
    << "[domain]\nlower = [-1.0, -0.5]\nupper = [3.0, 1.5]\nleaving = \"stop\"\n"
    << "[[shape]]\nname = \"outer\"\ntype = \"box\"\nlower = " << numbers({-e, -e}) << "\nupper = " << numbers({1 + e, 1 + e})
    << "\n[[shape]]\nname = \"inside\"\ntype = \"box\"\nlower = [0.0, 0.0]\nupper = [1.0, 1.0]\n"
    << "[[shape]]\nname = \"tank\"\ntype = \"difference\"\nshapes = [\"outer\", \"inside\"]\n"
    << "[[shape]]\nname = \"water\"\ntype = \"box\"\nlower = [0.0, 0.0]\nupper = [1.0, 0.5]\n" << extra
    << "[[body]]\nname = \"water\"\nkind = \"fluid\"\nshape = \"water\"\nvelocity = " << numbers(water_velocity) << "\n"
    << "[[body]]\nname = \"tank\"\nkind = \"wall\"\nshape = \"tank\"\n" << tank_motion
    << "[fluid]\ndensity = 1.0\nreference_velocity = 2.0\nsound_speed = 20.0\ncontinuity_dissipation = true\n"
    << "[physics]\ngravity = [0.0, -1.0]\n[initial]\nstate = \"hydrostatic\"\nfree_surface = 0.5\n"
    << (settling > 0 ? "settling_time = " + std::to_string(settling) + "\nsettling_damping = 1.0\n" : std::string())
    << "[time]\nend = 2.0\noutput_interval = 0.5\n";
  return s.str();
}

// A piston (a plate moving along x by a ramped sinusoid) and a flap (a plate hinged at the floor
// turning by a ramped sinusoid) in a tank at rest.
const std::string paddles =
    "[[shape]]\nname = \"piston\"\ntype = \"box\"\nlower = [0.2, 0.1]\nupper = [0.3, 0.9]\n"
    "[[shape]]\nname = \"flap\"\ntype = \"box\"\nlower = [0.7, 0.0]\nupper = [0.8, 0.9]\n"
    "[[body]]\nname = \"piston\"\nkind = \"wall\"\nshape = \"piston\"\nlayers = 2\n"
    "[body.translation]\nlaw = \"sinusoid\"\ndirection = [1.0, 0.0]\namplitude = 0.05\nperiod = 0.5\nramp_periods = 1\n"
    "[[body]]\nname = \"flap\"\nkind = \"wall\"\nshape = \"flap\"\nlayers = 2\n"
    "[body.rotation]\nlaw = \"sinusoid\"\npivot = [0.75, 0.0]\namplitude = 10.0\nperiod = 0.5\nphase = 90.0\nramp_periods = 1\n";

}  // namespace

UNISPH_POLICY_TEST_SUITE(MovingWalls);

TYPED_TEST(MovingWalls, PistonAndFlapFollowTheirLaws) {
  const CaseDescription c = parse_case(tank_case(0.05, "", {0.0, 0.0}, paddles), "moving_tank_2d.toml");
  WeaklyCompressibleSolver<double, 2> solver(c, kind_of<TypeParam>());
  // The wall's ids: the bodies' particles in the case's order (water is fluid): piston, flap, tank.
  const auto& groups = solver.wall_bodies();
  ASSERT_EQ(groups.size(), 3u);
  ASSERT_EQ(groups[0].name, "piston");
  ASSERT_EQ(groups[1].name, "flap");
  const std::vector<Vec<double, 2>> x0 = by_id<Vec<double, 2>>(solver.wall_body(), "InitialPosition");
  const std::vector<Vec<double, 2>> n0 = by_id<Vec<double, 2>>(solver.wall_body(), "InitialNormal");
  const double omega = 2 * std::numbers::pi / 0.5, ramp = 0.5, degrees = std::numbers::pi / 180;
  // The ramped sinusoid r(tau / T_r) A sin(omega tau + phase) and its rate (motion/time_law.hpp).
  const auto law = [&](double t, double amplitude, double phase, double& rate) {
    const double rho = std::min(t / ramp, 1.0);
    const double r = t < ramp ? rho * rho * rho * (10 + rho * (-15 + 6 * rho)) : 1.0;
    const double dr = t < ramp ? 30 * rho * rho * (1 - rho) * (1 - rho) / ramp : 0.0;
    rate = dr * amplitude * std::sin(omega * t + phase) + r * amplitude * omega * std::cos(omega * t + phase);
    return r * amplitude * std::sin(omega * t + phase);
  };
  double worst_position = 0, worst_velocity = 0, worst_normal = 0, largest_move = 0;
  int steps = 0;
  while (solver.time() < 1.0 - 1e-12) {
    solver.advance(1.0);
    ++steps;
    const double t = solver.time();
    const std::vector<Vec<double, 2>> x = by_id<Vec<double, 2>>(solver.wall_body(), "Position");
    const std::vector<Vec<double, 2>> n = by_id<Vec<double, 2>>(solver.wall_body(), "Normal");
    const std::vector<Vec<double, 2>> v = by_id<Vec<double, 2>>(solver.wall_body(), "Velocity");
    double ds = 0, dtheta = 0;
    const double s = law(t, 0.05, 0.0, ds), theta = law(t, 10 * degrees, 90 * degrees, dtheta);
    for (std::size_t k = 0; k < x.size(); ++k) {
      Vec<double, 2> expected_x = x0[k], expected_v{}, expected_n = n0[k];
      if (k < std::size_t(groups[0].count)) {  // piston
        expected_x[0] += s;
        expected_v[0] = ds;
      } else if (k < std::size_t(groups[0].count + groups[1].count)) {  // flap, about (0.75, 0)
        const double cs = std::cos(theta), sn = std::sin(theta);
        const double rx = x0[k][0] - 0.75, ry = x0[k][1];
        expected_x = Vec<double, 2>{{0.75 + cs * rx - sn * ry, sn * rx + cs * ry}};
        expected_v = Vec<double, 2>{{-(sn * rx + cs * ry) * dtheta, (cs * rx - sn * ry) * dtheta}};
        expected_n = Vec<double, 2>{{cs * n0[k][0] - sn * n0[k][1], sn * n0[k][0] + cs * n0[k][1]}};
      }
      worst_position = std::max(worst_position, norm(x[k] - expected_x));
      worst_velocity = std::max(worst_velocity, norm(v[k] - expected_v));
      worst_normal = std::max(worst_normal, norm(n[k] - expected_n));
      largest_move = std::max(largest_move, norm(x[k] - x0[k]));
    }
  }
  std::printf("%s: %d advection steps to t = 1 (2 periods): wall positions within %.2e, velocities within %.2e, normals "
              "within %.2e of the laws; largest displacement %.4f\n",
              std::string(TypeParam::test_label).c_str(), steps, worst_position, worst_velocity, worst_normal, largest_move);
  EXPECT_GT(largest_move, 0.04);
  // The laws are evaluated in unisph::Real: round-off of double, or of float in a
  // UNISPH_SINGLE_PRECISION build (the asan preset).
  const double round_off = sizeof(Real) == 8 ? 1e-12 : 1e-5;
  EXPECT_LT(worst_position, round_off);
  EXPECT_LT(worst_velocity, 100 * round_off);
  EXPECT_LT(worst_normal, round_off);
  EXPECT_EQ(solver.fluid_count(), solver.fluid_body().particles().owned_count());
}

TYPED_TEST(MovingWalls, TankAtConstantVelocityCarriesWaterAtRest) {
  const double dx = 0.05, speed = 0.25, depth = 0.5;
  const std::string motion = "[body.translation]\nlaw = \"constant\"\ndirection = [1.0, 0.0]\nvelocity = 0.25\n";
  // Settled first (20 time units, the walls held where they start, the water at rest), then the
  // water takes its initial velocity and the tank its motion, at time 0.
  WeaklyCompressibleSolver<double, 2> moving(parse_case(tank_case(dx, motion, {speed, 0.0}, "", 20.0), "moving_tank_2d.toml"),
                                             kind_of<TypeParam>());
  // The tank at rest is the same moving body at speed 0: both runs take the moving walls' path
  // and their neighbour search's cells (over the whole domain, which the moving tank sweeps), so
  // that the comparison sees the motion, not the round-off of another summation order.
  const std::string at_rest = replaced(motion, "velocity = 0.25", "velocity = 0.0");
  WeaklyCompressibleSolver<double, 2> still(parse_case(tank_case(dx, at_rest, {0.0, 0.0}, "", 20.0), "moving_tank_2d.toml"),
                                            kind_of<TypeParam>());
  double worst_relative = 0, worst_difference = 0, worst_still = 0;
  for (double t : {0.5, 1.0, 1.5, 2.0}) {
    while (moving.time() < t * (1 - 1e-12)) moving.advance(t);
    while (still.time() < t * (1 - 1e-12)) still.advance(t);
    const auto v = by_id<Vec<double, 2>>(moving.fluid_body(), "Velocity");
    const auto w = by_id<Vec<double, 2>>(still.fluid_body(), "Velocity");
    for (std::size_t i = 0; i < v.size(); ++i) {
      const Vec<double, 2> relative{{v[i][0] - speed, v[i][1]}};
      worst_relative = std::max(worst_relative, norm(relative));
      worst_difference = std::max(worst_difference, norm(relative - w[i]));
      worst_still = std::max(worst_still, norm(w[i]));
    }
  }
  const double scale = std::sqrt(1.0 * depth);
  const auto tank_x = by_id<Vec<double, 2>>(moving.wall_body(), "Position");
  const auto tank_x0 = by_id<Vec<double, 2>>(moving.wall_body(), "InitialPosition");
  std::printf("%s: tank at %.2f sqrt(g d) to t = 2 (moved %.4f): water velocity relative to the tank at most %.2e sqrt(g d) "
              "(issue 22's bound 1e-3: not met, as the still tank's own %.2e is not); the two fields %.2e apart (bound 1e-3)\n",
              std::string(TypeParam::test_label).c_str(), speed / scale, tank_x[0][0] - tank_x0[0][0], worst_relative / scale,
              worst_still / scale, worst_difference / scale);
  // The displacement 0.25 t at t = 2, at the round-off of unisph::Real (the law's arithmetic).
  EXPECT_NEAR(tank_x[0][0] - tank_x0[0][0], 0.5, sizeof(Real) == 8 ? 1e-12 : 1e-6);
  // The moving tank's water moves relative to it as the still tank's moves: the motion adds less
  // than 1e-3 sqrt(g d). The still tank's own residual motion after its settling (2.6e-2 sqrt(g d)
  // here, the drift of water at rest that issue 23 is about) bounds the relative velocity itself.
  EXPECT_LT(worst_difference, 1e-3 * scale);
}

// Static walls and the same walls moving at speed 0 give the same bits: the relaxations compile
// their common case (static walls, one rank) apart from the general kernel (InteractionDynamics::
// exec), and the two must sum the same terms in the same order (v - 0 and a - 0 are exact). With
// fluid.kernel_gradient_correction too: the corrected pressure relaxation's kernel derives from
// the plain one's, and its common case must still apply B (in session 22 it ran the base's
// uncorrected common case on one rank with static walls; this test would have caught it).
TYPED_TEST(MovingWalls, StaticWallsAndWallsMovingAtSpeedZeroGiveTheSameBits) {
  const std::string at_rest = "[body.translation]\nlaw = \"constant\"\ndirection = [1.0, 0.0]\nvelocity = 0.0\n";
  for (const bool corrected : {false, true}) {
    SCOPED_TRACE(corrected ? "kernel gradient corrected" : "plain pressure gradient");
    // The domain is the tank's outer box, so that both runs search the same cells (with static
    // walls the cells would otherwise cover only the particles' box, with moving ones the domain).
    const auto text = [&](const std::string& motion) {
      std::string t = replaced(tank_case(0.05, motion, {0.0, 0.0}), "lower = [-1.0, -0.5]\nupper = [3.0, 1.5]",
                               "lower = [-0.2, -0.2]\nupper = [1.2, 1.2]");
      return corrected ? replaced(t, "[fluid]\n", "[fluid]\nkernel_gradient_correction = true\n") : t;
    };
    WeaklyCompressibleSolver<double, 2> fixed(parse_case(text(""), "moving_tank_2d.toml"), kind_of<TypeParam>());
    WeaklyCompressibleSolver<double, 2> moving(parse_case(text(at_rest), "moving_tank_2d.toml"), kind_of<TypeParam>());
    while (fixed.time() < 0.5 - 1e-12) fixed.advance(0.5);
    while (moving.time() < 0.5 - 1e-12) moving.advance(0.5);
    EXPECT_EQ(fixed.advection_steps(), moving.advection_steps());
    using V = Vec<double, 2>;
    const auto v = by_id<V>(fixed.fluid_body(), "Velocity");
    double largest = 0;
    for (const V& x : v) largest = std::max(largest, norm(x));
    EXPECT_GT(largest, 0.0);  // the water moves (it starts on the lattice, unsettled): the terms are exercised
    for (const char* name : {"Position", "Velocity"})
      EXPECT_TRUE(by_id<V>(fixed.fluid_body(), name) == by_id<V>(moving.fluid_body(), name)) << name;
    EXPECT_TRUE(
        (by_id<double, double, 2>(fixed.fluid_body(), "Density") == by_id<double, double, 2>(moving.fluid_body(), "Density")));
  }
}

// A run with a moving wall, checkpointed at t = 0.5 and continued to t = 1 from the file, gives
// the same bits as the run that went on (seq).
TEST(HostMovingWalls, CheckpointRestartsBitForBit) {
  const CaseDescription c = parse_case(tank_case(0.05, "", {0.0, 0.0}, paddles), "moving_tank_2d.toml");
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "unisph_moving_walls_checkpoint.bin";
  WeaklyCompressibleSolver<double, 2> run(c, PolicyKind::seq);
  while (run.time() < 0.5 - 1e-12) run.advance(0.5);
  run.write_checkpoint(file, "");
  while (run.time() < 1.0 - 1e-12) run.advance(1.0);
  WeaklyCompressibleSolver<double, 2> restarted(c, PolicyKind::seq, false);
  restarted.restore_checkpoint(file);
  while (restarted.time() < 1.0 - 1e-12) restarted.advance(1.0);
  std::filesystem::remove(file);
  EXPECT_EQ(restarted.advection_steps(), run.advection_steps());
  for (const char* name : {"Position", "Velocity"}) {
    using V = Vec<double, 2>;
    EXPECT_TRUE(by_id<V>(restarted.fluid_body(), name) == by_id<V>(run.fluid_body(), name)) << "fluid " << name;
    EXPECT_TRUE(by_id<V>(restarted.wall_body(), name) == by_id<V>(run.wall_body(), name)) << "wall " << name;
  }
}

// Bad motions: one line naming the file, the line and the key.
TEST(HostMovingWalls, BrokenMotionsAreRefusedWithOneLine) {
  const std::string text = tank_case(0.05, "", {0.0, 0.0}, paddles);
  const std::filesystem::path table = std::filesystem::temp_directory_path() / "unisph_moving_walls_table.csv";
  {
    std::ofstream out(table);
    out << "time,displacement\n0.0,0.0\n0.5,0.01\n0.5,0.02\n";
  }
  const std::filesystem::path short_table = std::filesystem::temp_directory_path() / "unisph_moving_walls_short.csv";
  {
    std::ofstream out(short_table);
    out << "time,displacement\n0.0,0.0\n";
  }
  struct Broken {
    std::string text, expected;
  };
  const std::vector<Broken> cases = {
      {replaced(text, "law = \"sinusoid\"\ndirection", "law = \"wobble\"\ndirection"),
       "key 'body.translation.law': must be \"constant\", \"sinusoid\" or \"table\" (it is \"wobble\")"},
      {replaced(text, "direction = [1.0, 0.0]", "direction = [0.0, 0.0]"),
       "key 'body.translation.direction': must not be the zero vector"},
      {replaced(text, "period = 0.5\nramp_periods = 1\n[[body]]", "period = 0.0\nramp_periods = 1\n[[body]]"),
       "key 'body.translation.period': must be positive"},
      {replaced(text, "amplitude = 0.05\nperiod = 0.5\nramp_periods = 1\n", "file = \"" + table.string() + "\"\n"),
       "key 'body.translation.amplitude': missing value"},
      {replaced(replaced(text, "law = \"sinusoid\"\ndirection", "law = \"table\"\ndirection"),
                "amplitude = 0.05\nperiod = 0.5\nramp_periods = 1\n", "file = \"" + table.string() + "\"\n"),
       "key 'body.translation' (body 'piston'): " + table.string() + ":4:"},
      {replaced(replaced(text, "law = \"sinusoid\"\ndirection", "law = \"table\"\ndirection"),
                "amplitude = 0.05\nperiod = 0.5\nramp_periods = 1\n", "file = \"" + short_table.string() + "\"\n"),
       "key 'body.translation' (body 'piston'): " + short_table.string()},
      {replaced(text, "name = \"water\"\nkind = \"fluid\"\nshape = \"water\"\n",
                "name = \"water\"\nkind = \"fluid\"\nshape = \"water\"\n[body.translation]\nlaw = \"constant\"\n"),
       "key 'body.translation': unknown key"},
  };
  for (const Broken& b : cases) {
    try {
      WeaklyCompressibleSolver<double, 2> solver(parse_case(b.text, "moving_tank_2d.toml"), PolicyKind::seq);
      ADD_FAILURE() << "accepted; expected: " << b.expected;
    } catch (const CaseFileError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(b.expected), std::string::npos) << what << "\nexpected: " << b.expected;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_EQ(what.rfind("moving_tank_2d.toml:", 0), 0u) << what;
    }
  }
  std::filesystem::remove(table);
  std::filesystem::remove(short_table);
}
