// Tests of the SPH method pieces (include/unisph/sph/): kernel, Riemann limiter, tank
// particles, case-file errors (host), and the solver on every policy: 200 acoustic steps of
// the dam break agree with seq, mass is conserved exactly, water at rest stays at rest.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "support/policy_test.hpp"
#include "support/small_dam_break.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/sph/acoustic_riemann_solver.hpp"
#include "unisph/sph/density_diffusion.hpp"
#include "unisph/solver/case_file.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/solver/tank_particles.hpp"
#include "unisph/sph/wall_free_box.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"

using namespace unisph;
using namespace unisph::sph;

namespace {

template <int D>
double kernel_integral(double h_over_spacing) {
  // Sum of W over a fine lattice times the cell volume: the integral of W.
  const WendlandC2Kernel<double, D> w = WendlandC2Kernel<double, D>::from_spacing(1.0);
  const double spacing = w.h / h_over_spacing;
  double v = 1;
  for (int a = 0; a < D; ++a) v *= spacing;
  return w.lattice_sum(spacing) * v;
}

TEST(HostSphKernel, WendlandIntegratesToOne) {
  EXPECT_NEAR(kernel_integral<2>(20), 1.0, 1e-3);
  EXPECT_NEAR(kernel_integral<3>(12), 1.0, 2e-3);
  const auto w = WendlandC2Kernel<double, 2>::from_spacing(0.1);
  EXPECT_DOUBLE_EQ(w.h, 0.13);
  EXPECT_DOUBLE_EQ(w.cutoff(), 0.26);
  EXPECT_EQ(w.value(0.26), 0.0);
  EXPECT_EQ(w.derivative(0.0), 0.0);
}

TEST(HostSphKernel, DerivativeMatchesFiniteDifference) {
  const auto w = WendlandC2Kernel<double, 3>::from_spacing(0.02);
  for (double r = 0.001; r < w.cutoff(); r += 0.0013) {
    const double e = 1e-7;
    const double fd = (w.value(r + e) - w.value(r - e)) / (2 * e);
    EXPECT_NEAR(w.derivative(r), fd, 1e-6 * std::abs(w.value(0)) / w.h) << "r = " << r;
  }
}

TEST(HostSphRiemann, LimiterSwitchesOffForSeparatingPairs) {
  const auto s = AcousticRiemannSolver<double>::make(1000.0, 20.0);
  EXPECT_EQ(s.limiter(-1.0), 0.0);
  EXPECT_EQ(s.limiter(0.0), 0.0);
  EXPECT_DOUBLE_EQ(s.limiter(2.0), 0.3);
  EXPECT_EQ(s.limiter(100.0), 1.0);
  EXPECT_DOUBLE_EQ(s.twice_interface_pressure(3.0, 5.0, -4.0), 8.0);
  EXPECT_DOUBLE_EQ(s.twice_interface_pressure(3.0, 5.0, 40.0), 8.0 + 20000.0 * 40.0);
  EXPECT_DOUBLE_EQ(s.velocity_dissipation(20003.0, 3.0), 1.0);
}

TEST(HostSphTank, FourWallLayersWithUnitNormals) {
  const double dx = 0.1;
  const auto t = make_tank_particles<double, 2>({2.0, 1.5}, {1.0, 0.5}, dx);
  EXPECT_EQ(t.fluid.size(), 10u * 5u);
  EXPECT_EQ(t.wall.size(), std::size_t((20 + 8) * (15 + 8) - 20 * 15));
  for (std::size_t k = 0; k < t.wall.size(); ++k) {
    EXPECT_NEAR(std::hypot(t.wall_normal[k][0], t.wall_normal[k][1]), 1.0, 1e-12);
    EXPECT_GT(std::max({-t.wall[k][0], -t.wall[k][1], t.wall[k][0] - 2.0, t.wall[k][1] - 1.5}), 0.0);
    EXPECT_LT(std::max({-t.wall[k][0], -t.wall[k][1], t.wall[k][0] - 2.0, t.wall[k][1] - 1.5}), 4 * dx);
  }
  const auto t3 = make_tank_particles<double, 3>({1.0, 1.0, 0.5}, {0.5, 0.5, 0.5}, dx);
  EXPECT_EQ(t3.fluid.size(), 5u * 5u * 5u);
  EXPECT_EQ(t3.wall.size(), std::size_t(18 * 18 * 13 - 10 * 10 * 5));
}

// Any box of the tank's lattice made alone has the whole case's ids: the particles of the
// whole case whose position lies in the box, in the same order (a run on several ranks makes
// only each rank's share).
template <int D>
void expect_boxes_of_the_whole_case(const std::vector<double>& tank, const std::vector<double>& column, double dx) {
  const auto whole = make_tank_particles<double, D>(tank, column, dx);
  const TankLattice<D> lattice(tank, column, dx);
  ASSERT_EQ(lattice.fluid_count(), whole.fluid.size());
  ASSERT_EQ(lattice.wall_count(), whole.wall.size());
  const double boxes[4][2][3] = {{{-1, -1, -1}, {9, 9, 9}},
                                 {{0.25, 0.3, 0.1}, {0.75, 0.9, 0.35}},
                                 {{-0.5, 0.55, -0.5}, {0.5, 2.0, 0.2}},
                                 {{0.95, -0.5, 0.3}, {5.0, 0.05, 5.0}}};
  for (const auto& box : boxes) {
    const auto in_box = [&](const Vec<double, D>& x) {
      for (int a = 0; a < D; ++a)
        if (!(x[a] >= box[0][a] && x[a] < box[1][a])) return false;
      return true;
    };
    std::vector<std::uint64_t> expected, made;
    for (std::size_t k = 0; k < whole.fluid.size(); ++k)
      if (in_box(whole.fluid[k])) expected.push_back(k);
    lattice.fluid_within(box[0], box[1], [&](std::uint64_t id, const double* p) {
      made.push_back(id);
      for (int a = 0; a < D; ++a) EXPECT_EQ(p[a], whole.fluid[id][a]);
    });
    EXPECT_EQ(made, expected);
    expected.clear();
    made.clear();
    for (std::size_t k = 0; k < whole.wall.size(); ++k)
      if (in_box(whole.wall[k])) expected.push_back(k);
    lattice.walls_within(box[0], box[1], [&](std::uint64_t id, const double* p, const double* n) {
      made.push_back(id);
      for (int a = 0; a < D; ++a) {
        EXPECT_EQ(p[a], whole.wall[id][a]);
        EXPECT_EQ(n[a], whole.wall_normal[id][a]);
      }
    });
    EXPECT_EQ(made, expected);
  }
}

TEST(HostSphTank, AnyBoxOfTheLatticeHasTheWholeCasesIds) {
  expect_boxes_of_the_whole_case<2>({2.0, 1.5}, {1.0, 0.5}, 0.1);
  expect_boxes_of_the_whole_case<2>({1.07, 0.93}, {0.6, 0.45}, 0.05);
  expect_boxes_of_the_whole_case<3>({1.0, 1.0, 0.5}, {0.5, 0.5, 0.5}, 0.1);
  expect_boxes_of_the_whole_case<3>({1.13, 0.77, 0.41}, {0.52, 0.33, 0.41}, 0.05);
}

const char* valid_case = R"(
[case]
name = "t"
dimension = 2
[geometry]
dx = 0.1
tank = [2.0, 1.5]
column = [1.0, 0.5]
[fluid]
density = 1000.0
reference_velocity = 2.0
sound_speed = 20.0
[physics]
gravity = 9.81
[time]
end = 0.5
[[probe]]
name = "p1"
position = [2.0, 0.1]
)";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

std::string error_of(const std::string& text) {
  try {
    parse_case(text, "case.toml");
  } catch (const CaseFileError& e) {
    return e.what();
  }
  return "";
}

// Every point of the wall-free box is farther than the cutoff from every wall particle (the
// nearest point of the box to each is), so skipping the wall walk there drops no pair.
TEST(HostSphWallFreeBox, HoldsNoPointWithinTheCutoffOfTheWall) {
  for (const auto& [tank, dx] : {std::pair{std::vector<double>{5.366, 2.0}, 0.05}, {std::vector<double>{1.0, 0.7}, 0.013}}) {
    const TankParticles<float, 2> p = make_tank_particles<float, 2>(tank, {0.5, 0.5}, dx);
    const double cutoff = 2 * 1.3 * dx;
    const WallFreeBox<float, 2> box = WallFreeBox<float, 2>::of_tank(tank, p.wall, cutoff);
    ASSERT_LT(box.lower[0], box.upper[0]);
    double nearest = 1e300;
    for (const Vec<float, 2>& w : p.wall) {
      double d2 = 0;
      for (int a = 0; a < 2; ++a) {
        const double c = std::min(std::max(double(w[a]), double(box.lower[a])), double(box.upper[a]));
        d2 += (double(w[a]) - c) * (double(w[a]) - c);
      }
      nearest = std::min(nearest, std::sqrt(d2));
    }
    EXPECT_GT(nearest, cutoff);
    const Vec<float, 2> middle{float(tank[0] / 2), float(tank[1] / 2)};
    EXPECT_TRUE(box.contains(middle));
    std::vector<Vec<float, 2>> inside = p.wall;
    inside.push_back(middle);
    const WallFreeBox<float, 2> none = WallFreeBox<float, 2>::of_tank(tank, inside, cutoff);
    EXPECT_FALSE(none.contains(middle))
        << "a wall particle inside the tank empties the box";
  }
}

// A moving wall particle's swept box is kept clear of as a whole: a flume's piston swept
// +-0.05 along x, its floor and far wall at rest. The box keeps the cutoff from every point of
// every swept box, still holds the water beyond the piston's reach, and equals the box of the
// points where every extent is a point.
TEST(HostSphWallFreeBox, KeepsClearOfTheBoxesMovingWallsSweep) {
  using Extent = WallFreeBox<double, 2>::Extent;
  const double dx = 0.02, cutoff = 2 * 1.3 * dx;
  std::vector<Vec<double, 2>> points;
  std::vector<Extent> extents;
  const auto add = [&](double x, double y, double sweep) {
    points.push_back(Vec<double, 2>{x, y});
    extents.push_back(Extent{{x - sweep, y}, {x + sweep, y}});
  };
  for (int i = 0; i < 400; ++i)
    for (int k = 0; k < 4; ++k) add(-0.5 + (i + 0.5) * dx, -(k + 0.5) * dx, 0.0);  // the floor
  for (int j = 0; j < 60; ++j)
    for (int k = 0; k < 4; ++k) add(7.5 + (k + 0.5) * dx, (j + 0.5) * dx, 0.0);  // the far wall
  for (int j = 0; j < 75; ++j)
    for (int k = 0; k < 4; ++k) add(-(k + 0.5) * dx, (j + 0.5) * dx, 0.05);  // the piston
  const Vec<double, 2> lower{-1.0, -0.2}, upper{8.0, 2.0}, seed{3.0, 0.5};
  const WallFreeBox<double, 2> box = WallFreeBox<double, 2>::around(extents, lower, upper, seed, cutoff);
  ASSERT_LT(box.lower[0], box.upper[0]);
  double nearest = 1e300;
  for (const Extent& e : extents) {
    double d2 = 0;
    for (int a = 0; a < 2; ++a) {
      const double gap = std::max({e.lower[a] - box.upper[a], box.lower[a] - e.upper[a], 0.0});
      d2 += gap * gap;
    }
    nearest = std::min(nearest, std::sqrt(d2));
  }
  EXPECT_GT(nearest, cutoff);
  EXPECT_NEAR(box.lower[0], 0.05 - 0.5 * dx + 1.01 * cutoff, 1e-12) << "the piston's farthest reach plus the margin";
  EXPECT_TRUE(box.contains(seed));
  const WallFreeBox<double, 2> at_rest = WallFreeBox<double, 2>::around(points, lower, upper, seed, cutoff);
  for (auto& e : extents) e.lower[0] = e.upper[0] = 0.5 * (e.lower[0] + e.upper[0]);
  const WallFreeBox<double, 2> points_as_extents = WallFreeBox<double, 2>::around(extents, lower, upper, seed, cutoff);
  for (int a = 0; a < 2; ++a) {
    EXPECT_EQ(points_as_extents.lower[a], at_rest.lower[a]);
    EXPECT_EQ(points_as_extents.upper[a], at_rest.upper[a]);
  }
  EXPECT_LT(at_rest.lower[0], box.lower[0]);
}

TEST(HostSphCaseFile, ReadsAValidCase) {
  const CaseDescription c = parse_case(valid_case, "case.toml");
  EXPECT_EQ(c.name, "t");
  EXPECT_EQ(c.dx, 0.1);
  EXPECT_EQ(c.density, 1000.0);
  EXPECT_EQ(c.gravity, 9.81);
  ASSERT_EQ(c.probes.size(), 1u);
  EXPECT_EQ(c.probes[0].position[1], 0.1);
  EXPECT_EQ(c.output_interval, 0.01);
  EXPECT_EQ(c.settling_time, 0.0);
  EXPECT_EQ(c.smoothing_length_ratio, 1.3) << "h = 1.3 dx unless the case asks another";
  EXPECT_EQ(parse_case(replaced(valid_case, "dx = 0.1", "dx = 0.1\nsmoothing_length_ratio = 1.6"), "case.toml").smoothing_length_ratio, 1.6);
  const CaseDescription settled = parse_case(replaced(valid_case, "[physics]", "[initial]\nsettling_time = 3.0\n[physics]"), "case.toml");
  EXPECT_EQ(settled.settling_time, 3.0);
  EXPECT_EQ(settled.settling_damping, 2.0 / (2 * 0.5)) << "by default U over twice the column's height";
  const CaseDescription damped = parse_case(
      replaced(valid_case, "[physics]", "[initial]\nsettling_time = 3.0\nsettling_damping = 0.5\n[physics]"), "case.toml");
  EXPECT_EQ(damped.settling_damping, 0.5);
  // Comments may hold any UTF-8 (what toml++ is given has them as '?', case_file.cpp).
  const CaseDescription commented =
      parse_case(replaced(valid_case, "dx = 0.1", "dx = 0.1  # Wassers\xc3\xa4ule, \xef\xbb\xaf"), "case.toml");
  EXPECT_EQ(commented.dx, 0.1);
}

TEST(HostSphCaseFile, OneLineErrorsNameFileLineAndKey) {
  const std::map<std::string, std::string> cases = {
      {replaced(valid_case, "dx = 0.1", "dx = 0.1\nspacing = 2"), "case.toml:7: key 'geometry.spacing': unknown key"},
      {replaced(valid_case, "dx = 0.1", "dx = \"fine\""), "case.toml:6: key 'geometry.dx': must be a number"},
      {replaced(valid_case, "dx = 0.1", "dx = -0.1"), "case.toml:6: key 'geometry.dx': must be positive"},
      {replaced(valid_case, "dx = 0.1", "dx = 0"), "case.toml:6: key 'geometry.dx': must be positive"},
      {replaced(valid_case, "dx = 0.1", "dx = 0.1\nsmoothing_length_ratio = 0.8"),
       "case.toml:7: key 'geometry.smoothing_length_ratio': must be 1 to 2 (h / dx; 1.3 by default; it is 0.8)"},
      {replaced(valid_case, "dx = 0.1", "dx = 0.1\nsmoothing_length_ratio = 1.8"),
       "case.toml:7: key 'geometry.smoothing_length_ratio': the short form's tank has 4 layers of wall particles, which "
       "cover h up to 1.75 dx (it is 1.8)"},
      {replaced(valid_case, "gravity = 9.81", ""), "key 'physics.gravity': missing value"},
      {replaced(valid_case, "column = [1.0, 0.5]", "column = [3.0, 0.5]"), "case.toml:8: key 'geometry.column': the column"},
      {replaced(valid_case, "tank = [2.0, 1.5]", "tank = [2.0]"), "case.toml:7: key 'geometry.tank': must have 2 entries"},
      {replaced(valid_case, "end = 0.5", "end = 0.5 0.6"), "case.toml:16: not valid TOML"},
      {replaced(valid_case, "[physics]", "[initial]\nsettling_time = -1.0\n[physics]"),
       "case.toml:14: key 'initial.settling_time': must not be negative"},
      {replaced(valid_case, "[physics]", "[initial]\nsettling_damping = 1.0\n[physics]"),
       "case.toml:14: key 'initial.settling_damping': needs initial.settling_time > 0"},
      {replaced(valid_case, "[physics]", "[initial]\nsettling_time = 1.0\nsettling_damping = 0\n[physics]"),
       "case.toml:15: key 'initial.settling_damping': must be positive"},
      {replaced(valid_case, "density = 1000.0", "density = 1000.0\nfree_surface_density = 1"),
       "key 'fluid.free_surface_density': must be a string"},
      {replaced(valid_case, "density = 1000.0", "density = 1000.0\nfree_surface_density = \"max\""),
       "key 'fluid.free_surface_density': must be \"reference\", \"carried\" or \"none\" (it is \"max\")"},
      {replaced(valid_case, "density = 1000.0", "density = 1000.0\nwall_continuity = \"ghost\""),
       "key 'fluid.wall_continuity': must be \"mirror\" or \"kernel_sum\" (it is \"ghost\")"},
      {replaced(valid_case, "density = 1000.0", "density = 1000.0\nwall_pressure = \"mean\""),
       "key 'fluid.wall_pressure': must be \"extrapolated\" or \"averaged\" (it is \"mean\")"},
      {replaced(valid_case, "end = 0.5", "end = 0.5\nneighbor_search = \"grid\""),
       "case.toml:17: key 'time.neighbor_search': must be \"automatic\", \"stored\" or \"direct\" (it is \"grid\")"},
      {replaced(valid_case, "end = 0.5", "end = 0.5\nlast_acoustic_step = \"whole\""),
       "case.toml:17: key 'time.last_acoustic_step': must be \"shortened\" or \"full\" (it is \"whole\")"},
      // Values and keys that hold a line break are quoted with it escaped (found by fuzz/case_fuzzer.cpp):
      {replaced(valid_case, "[physics]", "[initial]\nstate = \"\"\"a\nb\"\"\"\n[physics]"),
       "case.toml:14: key 'initial.state': must be \"rest\" or \"hydrostatic\" (it is \"a\\nb\")"},
      {replaced(valid_case, "dx = 0.1", "dx = 0.1\n\"a\\nb\" = 2"), "case.toml:7: key 'geometry.a\\nb': unknown key"},
      // Inputs on which toml++ 3.x itself goes wrong (found by fuzz/case_fuzzer.cpp):
      {replaced(valid_case, "end = 0.5", "end = 0.5\nzna =4271-0---M 1#\xef\xbb\xaf"), "case.toml:17: not valid TOML"},
      {replaced(valid_case, "[physics]", "[ (physics)]"), "case.toml:13: not valid TOML: a table header must start"},
      {replaced(valid_case, "[physics]", "[\n"), "case.toml:13: not valid TOML: a table header must start"},
      {replaced(valid_case, "[physics]", "[tim\xe5]"), "case.toml:13: not valid TOML: the text is not valid UTF-8"},
      {replaced(valid_case, "gravity = 9.81", "gr\xc8\xbe" "avity = 9.81"), "case.toml:14: not valid TOML: a character that is not ASCII"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string message = error_of(text);
    EXPECT_NE(message.find(expected), std::string::npos) << "message: " << message << "\nexpected: " << expected;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

CaseDescription small_dam_break() {
  CaseDescription c = unisph::testing::small_dam_break();
  c.end_time = 1;
  c.output_interval = 1;
  c.continuity_dissipation = true;  // as every case in cases/ (the wall term of the continuity equation included)
  return c;
}

template <class T>
std::vector<Vec<T, 2>> positions_by_id(WeaklyCompressibleSolver<T, 2>& solver) {
  auto x = solver.fluid_body().positions().to_vector();
  auto id = solver.fluid_body().particles().ids().to_vector();
  std::vector<Vec<T, 2>> by_id(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) by_id[id[i]] = x[i];
  return by_id;
}

template <class T>
void run_acoustic_steps(WeaklyCompressibleSolver<T, 2>& solver, std::uint64_t steps) {
  while (solver.acoustic_steps() < steps) solver.advance(1e9);
}

// The largest distance between the same particle in two runs, over the tank's size (5.366).
template <class T>
double largest_position_difference(WeaklyCompressibleSolver<T, 2>& a, WeaklyCompressibleSolver<T, 2>& b) {
  const auto x = positions_by_id(a), y = positions_by_id(b);
  double worst = 0;
  for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, double(norm(x[i] - y[i])));
  return worst / 5.366;
}

}  // namespace

// time.last_acoustic_step: an advection step from rest ends at Dt = 0.25 h / U exactly when its
// last acoustic step is shortened; kept whole, it ends with the first acoustic step that reaches
// Dt (SPHinXsys' loop), and never past the time it was asked to stop at.
TEST(HostSphSolver, LastAcousticStepShortenedOrFull) {
  CaseDescription c = small_dam_break();
  const double h = 1.3 * c.dx, advection_dt = 0.25 * h / c.reference_velocity, acoustic_dt = 0.6 * h / c.sound_speed;
  WeaklyCompressibleSolver<double, 2> shortened(c, PolicyKind::seq);
  shortened.advance(1e9);
  EXPECT_NEAR(shortened.time(), advection_dt, 1e-15);
  EXPECT_EQ(shortened.acoustic_steps(), 5u) << "Dt / dt = 4.17 at rest";
  c.last_acoustic_step = "full";
  WeaklyCompressibleSolver<double, 2> full(c, PolicyKind::seq);
  full.advance(1e9);
  EXPECT_EQ(full.acoustic_steps(), 5u);
  EXPECT_GT(full.time(), advection_dt);
  EXPECT_LE(full.time(), 5 * acoustic_dt * (1 + 1e-15)) << "each step at most 0.6 h / c0";
  EXPECT_GT(full.time(), 5 * acoustic_dt * 0.99) << "speeds near rest: each step near 0.6 h / c0";
  WeaklyCompressibleSolver<double, 2> stopped(c, PolicyKind::seq);
  const double until = 1.1 * advection_dt;  // between Dt and five whole acoustic steps
  stopped.advance(until);
  EXPECT_NEAR(stopped.time(), until, 1e-15) << "a whole last step still stops at the time asked for";
}

UNISPH_POLICY_TEST_SUITE(SphSolver);

TYPED_TEST(SphSolver, DamBreakAgreesWithSeqAndConservesMass) {
  const PolicyKind kind = unisph::testing::kind_of<TypeParam>();
  WeaklyCompressibleSolver<double, 2> reference(small_dam_break(), PolicyKind::seq);
  WeaklyCompressibleSolver<double, 2> solver(small_dam_break(), kind);
  const ObserverSample s0 = solver.observe();
  const double mass0 = s0.mass;
  run_acoustic_steps(reference, 200);
  run_acoustic_steps(solver, 200);
  EXPECT_EQ(solver.acoustic_steps(), reference.acoustic_steps());
  EXPECT_EQ(solver.time(), reference.time()) << "the step sizes differ";
  const double relative = largest_position_difference(reference, solver);
  std::printf("[ measured ] 200+ acoustic steps on %s: largest position difference from seq %.3e of the tank size "
              "(bound 1e-9)\n",
              std::string(TypeParam::test_label).c_str(), relative);
  EXPECT_LE(relative, 1e-9);
  const ObserverSample s = solver.observe();
  EXPECT_EQ(s.mass, mass0) << "the mass of every particle is fixed";
  EXPECT_GT(s.kinetic_energy, 0.0);
  EXPECT_LE(s.kinetic_energy + s.potential_energy, (1 + 5e-3) * (s0.kinetic_energy + s0.potential_energy));
}

// The GPU's default: a direct search over cells of half the cutoff, which reads x_j from the
// neighbour records (neighbor_records.hpp); the same search on seq is the reference.
TYPED_TEST(SphSolver, DirectSearchThroughNeighborRecordsAgreesWithSeq) {
  const PolicyKind kind = unisph::testing::kind_of<TypeParam>();
  CaseDescription c = small_dam_break();
  c.neighbor_search = "direct";
  c.cells_per_cutoff = 2;
  WeaklyCompressibleSolver<double, 2> reference(c, PolicyKind::seq);
  WeaklyCompressibleSolver<double, 2> solver(c, kind);
  const double mass0 = solver.observe().mass;
  run_acoustic_steps(reference, 200);
  run_acoustic_steps(solver, 200);
  EXPECT_EQ(solver.acoustic_steps(), reference.acoustic_steps());
  const double relative = largest_position_difference(reference, solver);
  std::printf("[ measured ] 200+ acoustic steps, direct search, on %s: largest position difference from seq %.3e of "
              "the tank size (bound 1e-9)\n",
              std::string(TypeParam::test_label).c_str(), relative);
  EXPECT_LE(relative, 1e-9);
  if (kind == PolicyKind::par) {
    EXPECT_EQ(relative, 0.0) << "par reproduces seq bit for bit";
  }
  EXPECT_EQ(solver.observe().mass, mass0);
}

// Between advection steps (after the sort) the neighbour records hold exactly {x, m/rho} and
// {v, p} of the fluid variables, in their order: a stale record would go unnoticed by a
// comparison with seq, which would read the same stale values.
TYPED_TEST(SphSolver, NeighborRecordsFollowTheFluidVariables) {
  const PolicyKind kind = TypeParam::space == MemorySpace::device ? PolicyKind::device
                          : std::is_same_v<TypeParam, SequencedPolicy> ? PolicyKind::seq
                                                                       : PolicyKind::par;
  for (const char* search : {"direct", "stored"}) {
    CaseDescription c = small_dam_break();
    c.neighbor_search = search;
    WeaklyCompressibleSolver<float, 2> solver(c, kind);
    run_acoustic_steps(solver, 60);
    auto& set = solver.fluid_body().particles();
    const auto x = set.template variable<Vec<float, 2>>("Position").to_vector();
    const auto v = set.template variable<Vec<float, 2>>("Velocity").to_vector();
    const auto p = set.template variable<float>("Pressure").to_vector();
    const auto m = set.template variable<float>("Mass").to_vector();
    const auto rho = set.template variable<float>("Density").to_vector();
    const auto xv = set.template variable<PositionVolume<float, 2>>("NeighborPositionVolume").to_vector();
    const auto vp = set.template variable<VelocityPressure<float, 2>>("NeighborVelocityPressure").to_vector();
    ASSERT_EQ(xv.size(), x.size());
    ASSERT_EQ(vp.size(), x.size());
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      const bool same = xv[i].position[0] == x[i][0] && xv[i].position[1] == x[i][1] &&
                        xv[i].volume == m[i] / rho[i] && vp[i].velocity[0] == v[i][0] &&
                        vp[i].velocity[1] == v[i][1] && vp[i].pressure == p[i];
      wrong += same ? 0 : 1;
    }
    EXPECT_EQ(wrong, 0u) << search << " search: records that differ from the fluid variables";
  }
}

TYPED_TEST(SphSolver, FloatRunsAndWaterAtRestStaysAtRest) {
  const PolicyKind kind = TypeParam::space == MemorySpace::device ? PolicyKind::device
                          : std::is_same_v<TypeParam, SequencedPolicy> ? PolicyKind::seq
                                                                       : PolicyKind::par;
  CaseDescription c = small_dam_break();
  c.tank = {2.0, 1.5};
  c.column = {2.0, 1.0};
  c.hydrostatic = true;
  WeaklyCompressibleSolver<float, 2> solver(c, kind);
  while (solver.time() < 1.0) solver.advance(1.0);
  const ObserverSample s = solver.observe();
  // A quick sanity check at dx = H/20 through the start-up transient; the issue's bound (1e-3
  // at t = 50, dx = H/40) is checked by the validation test HydrostaticTank.
  std::printf("[ measured ] hydrostatic tank after t = 1 on %s (float): kinetic / potential energy %.3e (sanity bound 1e-2)\n",
              std::string(TypeParam::test_label).c_str(), s.kinetic_energy / s.potential_energy);
  EXPECT_LT(s.kinetic_energy, 1e-2 * s.potential_energy);
}

// The density from the continuity equation alone, with delta-SPH's density diffusion
// (fluid.density_method = "continuity", fluid.density_diffusion; what the dam-break cases use):
// 200 acoustic steps of the dam break agree with seq on every policy, and mass is kept.
TYPED_TEST(SphSolver, ContinuityDensityWithDiffusionAgreesWithSeq) {
  const PolicyKind kind = unisph::testing::kind_of<TypeParam>();
  CaseDescription c = small_dam_break();
  c.density_method = "continuity";
  c.continuity_dissipation = false;  // delta-SPH's diffusion instead of the Riemann dissipation
  c.density_diffusion = 0.1;
  WeaklyCompressibleSolver<double, 2> reference(c, PolicyKind::seq);
  WeaklyCompressibleSolver<double, 2> solver(c, kind);
  const double mass0 = solver.observe().mass;
  run_acoustic_steps(reference, 200);
  run_acoustic_steps(solver, 200);
  EXPECT_EQ(solver.acoustic_steps(), reference.acoustic_steps());
  const double relative = largest_position_difference(reference, solver);
  std::printf("[ measured ] continuity density with diffusion, 200+ acoustic steps on %s: largest position difference "
              "from seq %.3e of the tank size (bound 1e-9)\n",
              std::string(TypeParam::test_label).c_str(), relative);
  EXPECT_LE(relative, 1e-9);
  EXPECT_EQ(solver.observe().mass, mass0);
}

// A method option: 200+ dam-break acoustic steps with it (`with`) on `kind` give seq's run within
// 1e-9 of the tank size, differ from the run without it (`without`: the option reaches the
// kernels), and keep the mass.
void expect_option_agrees_with_seq(const CaseDescription& with, const CaseDescription& without, PolicyKind kind,
                                   const std::string& label, const char* option, const char* other) {
  WeaklyCompressibleSolver<double, 2> reference(with, PolicyKind::seq);
  WeaklyCompressibleSolver<double, 2> solver(with, kind);
  WeaklyCompressibleSolver<double, 2> unchanged(without, kind);
  const double mass0 = solver.observe().mass;
  run_acoustic_steps(reference, 200);
  run_acoustic_steps(solver, 200);
  run_acoustic_steps(unchanged, 200);
  EXPECT_EQ(solver.acoustic_steps(), reference.acoustic_steps());
  const double relative = largest_position_difference(reference, solver);
  const double from_other = largest_position_difference(unchanged, solver);
  std::printf("[ measured ] %s, 200+ acoustic steps on %s: largest position difference from seq %.3e of the tank size "
              "(bound 1e-9); from the %s run %.3e\n",
              option, label.c_str(), relative, other, from_other);
  EXPECT_LE(relative, 1e-9);
  EXPECT_GT(from_other, 1e-7) << "the option changes the run";
  EXPECT_EQ(solver.observe().mass, mass0);
}

// fluid.wall_continuity = "kernel_sum": the continuity equation's wall term as the rate of the
// kernel sum over the wall particles (density_relaxation.hpp, WallContinuity), against the mirror's.
TYPED_TEST(SphSolver, WallContinuityAsKernelSumAgreesWithSeq) {
  CaseDescription c = small_dam_break();
  c.wall_continuity = "kernel_sum";
  expect_option_agrees_with_seq(c, small_dam_break(), unisph::testing::kind_of<TypeParam>(),
                                std::string(TypeParam::test_label), "wall term as the kernel sum's rate", "mirror's");
}

// fluid.wall_pressure = "averaged" (wall_pressure_average.hpp), with the method it is offered for
// (the carried density, delta = 0.1, the kernel-sum wall term), against the extrapolated pressure.
TYPED_TEST(SphSolver, AveragedWallPressureAgreesWithSeq) {
  CaseDescription c = small_dam_break();
  c.density_method = "continuity";
  c.continuity_dissipation = false;
  c.density_diffusion = 0.1;
  c.wall_continuity = "kernel_sum";
  CaseDescription extrapolated = c;
  c.wall_pressure = "averaged";
  expect_option_agrees_with_seq(c, extrapolated, unisph::testing::kind_of<TypeParam>(),
                                std::string(TypeParam::test_label), "averaged wall pressure",
                                "extrapolated pressure's");
}

// Each wall particle's averaged pressure against a brute-force Shepard average over every fluid
// particle (1e-12 of rho0 g H), and, in a tank at rest, against the hydrostatic pressure at the
// wall particle's own depth, which the average reproduces whatever the weights (each term is
// p_f + rho_f g.(x_w - x_f) = rho0 g (H - y_w) + (rho_f - rho0) g (y_f - y_w); the last part is at
// most g H / c0^2 = 1/400 of rho0 g H times 2h, hence the bound 1e-3 of rho0 g H): the floor's and
// the side walls' particles below the free surface; 0 where no fluid is within the cutoff. Taken
// before any step, from the initial hydrostatic state (the lattice's start-up moves it by more).
TYPED_TEST(SphSolver, AveragedWallPressureIsTheShepardAverageAndHydrostaticAtRest) {
  const PolicyKind kind = unisph::testing::kind_of<TypeParam>();
  CaseDescription c = small_dam_break();
  c.tank = {2.0, 1.5};
  c.column = {2.0, 1.0};
  c.hydrostatic = true;
  c.density_method = "continuity";
  c.continuity_dissipation = false;
  c.wall_pressure = "averaged";
  WeaklyCompressibleSolver<double, 2> solver(c, kind);
  solver.pressure_relaxation_pass();  // the walls' pressures from the initial state (a step would move it)
  auto& fluid = solver.fluid_body().particles();
  auto& wall = solver.wall_body().particles();
  const auto xf = fluid.template variable<Vec<double, 2>>("Position").to_vector();
  const auto pf = fluid.template variable<double>("Pressure").to_vector();
  const auto rf = fluid.template variable<double>("Density").to_vector();
  const auto xw = wall.template variable<Vec<double, 2>>("Position").to_vector();
  const auto pw = wall.template variable<double>("WallPressure").to_vector();
  ASSERT_EQ(pw.size(), xw.size());
  const WendlandC2Kernel<double, 2> kernel = WendlandC2Kernel<double, 2>::from_spacing(c.dx);
  const Vec<double, 2> g{{0.0, -c.gravity}};
  const double scale = c.density * c.gravity * c.column[1];
  double worst_average = 0, worst_hydrostatic = 0;
  std::size_t wet = 0, dry = 0;
  for (std::size_t w = 0; w < xw.size(); ++w) {
    double weighted = 0, weight = 0;
    for (std::size_t f = 0; f < xf.size(); ++f) {
      const double r = std::sqrt(squared_norm(Vec<double, 2>(xw[w] - xf[f])));
      if (r >= kernel.cutoff()) continue;
      const double W = kernel.value(r);
      weighted += W * (pf[f] + rf[f] * dot(g, Vec<double, 2>(xw[w] - xf[f])));
      weight += W;
    }
    const double expected = weight > 0 ? std::max(weighted / weight, 0.0) : 0.0;
    worst_average = std::max(worst_average, std::abs(pw[w] - expected) / scale);
    if (weight == 0) {
      ++dry;
    } else if (xw[w][1] < c.column[1] - kernel.cutoff()) {
      ++wet;
      worst_hydrostatic =
          std::max(worst_hydrostatic, std::abs(pw[w] - c.density * c.gravity * (c.column[1] - xw[w][1])) / scale);
    }
  }
  std::printf("[ measured ] averaged wall pressure on %s: %zu wall particles below the surface, %zu dry; "
              "largest difference from the brute-force average %.2e (bound 1e-12), from the hydrostatic pressure "
              "%.2e (bound 1e-3) of rho0 g H\n",
              std::string(TypeParam::test_label).c_str(), wet, dry, worst_average, worst_hydrostatic);
  EXPECT_GT(wet, 20u);
  EXPECT_GT(dry, 20u);
  EXPECT_LE(worst_average, 1e-12);
  EXPECT_LE(worst_hydrostatic, 1e-3);
}

// The density-diffusion term (sph/density_diffusion.hpp) summed by brute force over a square
// lattice of particles, for a pressure field given per particle.
template <class T>
struct DiffusionOverLattice {
  View<const Vec<T, 2>> x;
  View<const T> p;
  View<T> rate;
  Index n;
  WendlandC2Kernel<T, 2> kernel;
  sph::DensityDiffusion<T, 2> diffusion;
  T volume;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    T sum = T(0);
    for (Index j = 0; j < n; ++j) {
      if (j == i) continue;
      NeighborPair<T, 2> pair;
      pair.r_ij = x[i] - x[j];
      pair.squared_distance = squared_norm(pair.r_ij);
      if (pair.squared_distance >= kernel.cutoff() * kernel.cutoff()) continue;
      pair.complete();
      sum += diffusion.pair_term(p[i], p[j], pair, kernel.derivative(pair.r), volume);
    }
    rate[i] = diffusion.coefficient * sum;
  }
};

// With the hydrostatic part taken out, the term is zero pair by pair in a hydrostatic pressure
// field, whatever the direction of gravity (edges included: no particle needs a full support);
// for a density field rho0 + A x^2 without gravity it is delta h c0 times the Laplacian 2A,
// within the lattice moment of the kernel's Laplacian (0.964 in 2D at h = 1.3 dx).
TYPED_TEST(SphSolver, DensityDiffusionVanishesInHydrostaticBalanceAndDiffusesCurvature) {
  const int side = 20;
  const Index n = side * side;
  const double dx = 0.05, rho0 = 1000, c0 = 20, delta = 0.1;
  const WendlandC2Kernel<double, 2> kernel = WendlandC2Kernel<double, 2>::from_spacing(dx);
  std::vector<Vec<double, 2>> x(n);
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b) x[std::size_t(a * side + b)] = Vec<double, 2>{{(a + 0.5) * dx, (b + 0.5) * dx}};
  const auto rates = [&](const Vec<double, 2>& g, const std::vector<double>& p) {
    DiscreteVariable<Vec<double, 2>> xs("x");
    DiscreteVariable<double> ps("p"), out("rate", n);
    xs.assign(x);
    ps.assign(p);
    particle_for(this->policy, n,
                 DiffusionOverLattice<double>{xs.read(this->policy), ps.read(this->policy), out.write(this->policy), n,
                                              kernel, sph::DensityDiffusion<double, 2>::make(delta, kernel.h, c0, rho0, g),
                                              dx * dx});
    return out.to_vector();
  };
  // Hydrostatic: p = rho0 g . (x - x_surface), with gravity tilted.
  const Vec<double, 2> g{{3.0, -4.0}};
  std::vector<double> hydrostatic(n);
  for (Index i = 0; i < n; ++i) hydrostatic[i] = rho0 * dot(g, x[i] - Vec<double, 2>{{0.0, 1.0}});
  double worst = 0;
  for (double r : rates(g, hydrostatic)) worst = std::max(worst, std::abs(r));
  // Scale: one pair's share without the hydrostatic part, rho0 |g| dx / c0^2 times delta h c0 / dx^2.
  const double scale = delta * kernel.h * c0 * rho0 * 5.0 * dx / (c0 * c0) / (dx * dx);
  // Curvature: rho - rho0 = A x^2, p = c0^2 A x^2, no gravity; interior particles only.
  const double A = 2.0;
  std::vector<double> curved(n);
  for (Index i = 0; i < n; ++i) curved[i] = c0 * c0 * A * x[i][0] * x[i][0];
  const auto r = rates(Vec<double, 2>{}, curved);
  const double expected = delta * kernel.h * c0 * 2 * A;
  double worst_ratio = 0;
  for (Index i = 0; i < n; ++i)
    if (std::min({x[i][0], x[i][1], side * dx - x[i][0], side * dx - x[i][1]}) > kernel.cutoff())
      worst_ratio = std::max(worst_ratio, std::abs(r[i] / expected - 1));
  std::printf("[ measured ] density diffusion on %s: hydrostatic field %.2e of a pair's scale (bound 1e-12); "
              "curvature A x^2: rate / (delta h c0 2A) within %.4f of 1 (bound 0.05)\n",
              std::string(TypeParam::test_label).c_str(), worst / scale, worst_ratio);
  EXPECT_LE(worst / scale, 1e-12);
  EXPECT_LE(worst_ratio, 0.05);
}

// The settling stage (initial.settling_time): the water is moved under damping before time 0,
// then starts at rest from where it came to, with the clock and the step counters at 0. Its
// steps are the solver's own, so par reproduces seq bit for bit and the device within round-off.
TYPED_TEST(SphSolver, SettlingStartsAtRestAtTimeZeroAndAgreesWithSeq) {
  const PolicyKind kind = TypeParam::space == MemorySpace::device ? PolicyKind::device
                          : std::is_same_v<TypeParam, SequencedPolicy> ? PolicyKind::seq
                                                                       : PolicyKind::par;
  CaseDescription c = small_dam_break();
  c.dx = 0.1;
  c.tank = {2.0, 1.5};
  c.column = {2.0, 1.0};
  c.hydrostatic = true;
  c.probes.clear();
  c.settling_time = 2.0;
  c.settling_damping = 1.0;
  CaseDescription unsettled = c;
  unsettled.settling_time = 0;
  WeaklyCompressibleSolver<double, 2> lattice(unsettled, PolicyKind::seq);
  WeaklyCompressibleSolver<double, 2> reference(c, PolicyKind::seq);
  WeaklyCompressibleSolver<double, 2> solver(c, kind);
  EXPECT_EQ(solver.time(), 0.0);
  EXPECT_EQ(solver.advection_steps(), 0u);
  EXPECT_EQ(solver.acoustic_steps(), 0u);
  EXPECT_GE(solver.settling().time, c.settling_time * (1 - 1e-12));
  EXPECT_GT(solver.settling().acoustic_steps, solver.settling().advection_steps);
  EXPECT_EQ(solver.settling().advection_steps, reference.settling().advection_steps);
  EXPECT_EQ(lattice.settling().advection_steps, 0u);
  for (const auto& v : solver.fluid_body().particles().template variable<Vec<double, 2>>("Velocity").to_vector())
    ASSERT_TRUE(v[0] == 0.0 && v[1] == 0.0) << "the settled water starts at rest";
  // Every particle keeps its mass (compared by id: the device's total sums in another order).
  const auto masses_by_id = [](WeaklyCompressibleSolver<double, 2>& s) {
    auto m = s.fluid_body().particles().template variable<double>("Mass").to_vector();
    auto id = s.fluid_body().particles().ids().to_vector();
    std::vector<double> out(m.size());
    for (std::size_t i = 0; i < m.size(); ++i) out[id[i]] = m[i];
    return out;
  };
  EXPECT_EQ(masses_by_id(solver), masses_by_id(lattice)) << "settling keeps every particle's mass";
  const auto x = positions_by_id(solver), x_seq = positions_by_id(reference), x_lattice = positions_by_id(lattice);
  double from_seq = 0, from_lattice = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    from_seq = std::max(from_seq, norm(x[i] - x_seq[i]) / c.tank[0]);
    from_lattice = std::max(from_lattice, norm(x[i] - x_lattice[i]));
  }
  std::printf("[ measured ] settling on %s: largest move from the lattice %.3e dx; from seq %.2e of the tank\n",
              std::string(TypeParam::test_label).c_str(), from_lattice / c.dx, from_seq);
  EXPECT_GT(from_lattice, 1e-3 * c.dx) << "the water settled somewhere";
  if (kind == PolicyKind::device) {
    EXPECT_LE(from_seq, 1e-9);
  } else {
    EXPECT_EQ(from_seq, 0.0);
  }
}
