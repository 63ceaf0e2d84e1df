// The general form of a case (case_description.hpp: [domain], [[shape]], [[body]], gravity as a
// vector) through the solver, on every policy:
//  * the hydrostatic tank written with shapes makes the short form's particles and runs as it
//    does (the same positions at the start; the same state to round-off after 100 steps);
//  * the dam break onto a wedge (a box cut by a half-space) on seq, par and the GPU agrees to
//    1e-9 relative after 200 advection steps (double);
//  * water running off a ledge leaves an open domain: every particle removed is counted, and
//    the mass left plus the mass removed is the initial mass exactly;
//  * broken general-form cases are refused with one line naming the file, the line and the key.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "support/by_id.hpp"
#include "support/case_text.hpp"
#include "support/policy_test.hpp"
#include "unisph/solver/case_file.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"

using namespace unisph;
using namespace unisph::sph;
using unisph::testing::by_id;
using unisph::testing::file_text;
using unisph::testing::kind_of;
using unisph::testing::replaced;

namespace {

template <class T, int D>
double largest_difference(const std::vector<Vec<T, D>>& a, const std::vector<Vec<T, D>>& b) {
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < D; ++k) worst = std::max(worst, std::abs(double(a[i][k]) - double(b[i][k])));
  return worst;
}

// hydrostatic_2d.toml and hydrostatic_general_2d.toml, started without settling.
CaseDescription unsettled(const std::string& file) {
  std::string text = file_text(std::string(UNISPH_CASES_DIR) + "/" + file);
  text = replaced(text, "settling_time = 40.0", "settling_time = 0.0");
  text = replaced(text, "settling_damping = 1.0", "");
  return parse_case(text, file);
}

// A ledge in an open domain; the water runs off both ends and falls out of the bottom.
std::string ledge_case(const std::string& leaving) {
  return R"(
[case]
name = "ledge"
[geometry]
dx = 0.0625
[domain]
lower = [-1.5, -1.0]
upper = [3.5, 2.0]
)" + leaving + R"(
[[shape]]
name = "ledge"
type = "box"
lower = [0.0, -0.25]
upper = [2.0, 0.0]
[[shape]]
name = "water"
type = "box"
lower = [0.5, 0.0]
upper = [1.5, 0.5]
[[body]]
name = "ledge"
kind = "wall"
shape = "ledge"
[[body]]
name = "water"
kind = "fluid"
shape = "water"
[fluid]
density = 1.0
reference_velocity = 3.0
sound_speed = 30.0
[physics]
gravity = [0.0, -1.0]
[time]
end = 10.0
)";
}

}  // namespace

UNISPH_POLICY_TEST_SUITE(GeneralForm);

TYPED_TEST(GeneralForm, HydrostaticTankWithShapesIsTheShortForm) {
  if (sizeof(Real) == 4)
    GTEST_SKIP() << "this build computes shapes in unisph::Real = float (UNISPH_SINGLE_PRECISION): the lattice this check "
                    "compares to the last bit of double is not the same (docs/sph.md, \"The general form\")";
  const PolicyKind kind = kind_of<TypeParam>();
  WeaklyCompressibleSolver<double, 2> short_form(unsettled("hydrostatic_2d.toml"), kind);
  WeaklyCompressibleSolver<double, 2> general(unsettled("hydrostatic_general_2d.toml"), kind);
  ASSERT_EQ(general.fluid_count(), short_form.fluid_count());
  ASSERT_EQ(general.wall_bodies().size(), 1u);
  EXPECT_EQ(general.wall_bodies()[0].name, "tank");
  EXPECT_EQ(general.removed_fluid_count(), 0);
  // The same fluid particles at the start, id by id.
  EXPECT_EQ(largest_difference(by_id(general.fluid_body(), "Position"), by_id(short_form.fluid_body(), "Position")), 0.0);
  // The wall: the shape's layers are 4 dx deep from the inner box (Euclidean), the tank's a
  // square band, so the tank has a few more particles in its outer corners, more than 4 dx from
  // the inside, which no fluid particle reaches. Every particle of the shape's wall is one of the
  // tank's (the lattice's origin + (i + 1/2) dx against the tank's -(k + 1/2) dx: the last bit
  // may differ); its normal is the tank's where a fluid particle can see it (within 0.5 dx + the
  // cutoff 2.6 dx of the inside).
  {
    const double dx = 0.025;
    const auto key = [&](const Vec<double, 2>& x) { return std::pair{std::lround(x[0] / dx * 2), std::lround(x[1] / dx * 2)}; };
    std::map<std::pair<long, long>, std::size_t> tank;
    const auto tank_x = by_id(short_form.wall_body(), "Position"), tank_n = by_id(short_form.wall_body(), "Normal");
    for (std::size_t k = 0; k < tank_x.size(); ++k) tank[key(tank_x[k])] = k;
    const auto wall_x = by_id(general.wall_body(), "Position"), wall_n = by_id(general.wall_body(), "Normal");
    double position = 0, worst = 0;
    int reachable = 0, missing = 0;
    for (std::size_t k = 0; k < wall_x.size(); ++k) {
      const auto found = tank.find(key(wall_x[k]));
      if (found == tank.end()) {
        ++missing;
        continue;
      }
      const std::size_t t = found->second;
      tank.erase(found);
      position = std::max(position, std::max(std::abs(wall_x[k][0] - tank_x[t][0]), std::abs(wall_x[k][1] - tank_x[t][1])));
      const double ox = std::max({0.0, -wall_x[k][0], wall_x[k][0] - 2.0}), oy = std::max({0.0, -wall_x[k][1], wall_x[k][1] - 1.5});
      if (std::hypot(ox, oy) < 3.1 * dx) {
        ++reachable;
        worst = std::max(worst, std::max(std::abs(wall_n[k][0] - tank_n[t][0]), std::abs(wall_n[k][1] - tank_n[t][1])));
      }
    }
    double nearest_extra = 1e9;
    for (const auto& [k, t] : tank) {
      const double ox = std::max({0.0, -tank_x[t][0], tank_x[t][0] - 2.0}), oy = std::max({0.0, -tank_x[t][1], tank_x[t][1] - 1.5});
      nearest_extra = std::min(nearest_extra, std::hypot(ox, oy) / dx);
    }
    std::printf("wall: %d of the shape's particles are the tank's (positions within %.3g), %d are not; the tank's %d others lie "
                "%.3g dx or more from the inside; normals within the fluid's reach (%d): largest difference %.3g\n",
                int(wall_x.size()) - missing, position, missing, int(tank.size()), nearest_extra, reachable, worst);
    EXPECT_EQ(missing, 0);
    EXPECT_LT(position, 1e-15);
    EXPECT_GT(nearest_extra, 4.0);
    EXPECT_LT(worst, 1e-4) << "central differences of step dx / 100 at the corners";
  }
  for (int step = 0; step < 100; ++step) {
    short_form.advance(1e9);
    general.advance(1e9);
  }
  const double dx = 0.025;
  const double positions = largest_difference(by_id(general.fluid_body(), "Position"), by_id(short_form.fluid_body(), "Position"));
  const ObserverSample a = short_form.observe(), b = general.observe();
  std::printf("after 100 advection steps (t = %.4f): positions differ by %.3g dx at most; probe 0.5 H %.9f / %.9f\n",
              general.time(), positions / dx, a.probe_pressure[1], b.probe_pressure[1]);
  EXPECT_EQ(general.time(), short_form.time());
  EXPECT_LT(positions, 1e-9 * dx);
  for (std::size_t k = 0; k < a.probe_pressure.size(); ++k) EXPECT_NEAR(b.probe_pressure[k], a.probe_pressure[k], 1e-9);
}

// 200 acoustic steps, as the short form's DamBreakAgreesWithSeq (test_sph_methods): the flow's
// own growth of differences then stays below round-off's reach; the same method on every policy
// (stored lists: "automatic" would take the direct search on the GPU, another geometry per step).
TYPED_TEST(GeneralForm, WedgeDamBreakAgreesWithSeq) {
  const std::string path = std::string(UNISPH_CASES_DIR) + "/dambreak_wedge_2d.toml";
  CaseDescription c = read_case_file(path);
  c.neighbor_search = "stored";
  WeaklyCompressibleSolver<double, 2> reference(c, PolicyKind::seq);
  WeaklyCompressibleSolver<double, 2> solver(c, kind_of<TypeParam>());
  ASSERT_EQ(solver.wall_bodies().size(), 2u);
  EXPECT_EQ(solver.wall_bodies()[1].name, "wedge");
  EXPECT_GT(solver.wall_bodies()[1].count, 0);
  while (reference.acoustic_steps() < 200) reference.advance(1e9);
  while (solver.acoustic_steps() < 200) solver.advance(1e9);
  const auto x = by_id(solver.fluid_body(), "Position"), x_ref = by_id(reference.fluid_body(), "Position");
  const auto v = by_id(solver.fluid_body(), "Velocity"), v_ref = by_id(reference.fluid_body(), "Velocity");
  const double position = largest_difference(x, x_ref) / 5.366;
  double speed = 0;
  for (const auto& u : v_ref) speed = std::max(speed, double(norm(u)));
  const double velocity = largest_difference(v, v_ref) / speed;
  std::printf("%s after 200+ acoustic steps (t = %.4f, %d wedge particles): position %.3g, velocity %.3g relative to seq\n",
              std::string(TypeParam::test_label).c_str(), solver.time(), int(solver.wall_bodies()[1].count), position, velocity);
  EXPECT_EQ(solver.advection_steps(), reference.advection_steps());
  EXPECT_LE(position, 1e-9);
  EXPECT_LE(velocity, 1e-9);
}

TYPED_TEST(GeneralForm, WaterLeavingTheDomainIsCountedAndMassIsKept) {
  // dx is a power of 2 and the water starts at rest at rho0, so every mass is the same exact number
  // and the sums below are exact.
  const CaseDescription c = parse_case(ledge_case(""), "ledge.toml");
  EXPECT_EQ(c.domain.leaving, "remove") << "the general form's default";
  WeaklyCompressibleSolver<double, 2> solver(c, kind_of<TypeParam>());
  const Index initial = solver.fluid_count();
  const double initial_mass = solver.observe().mass;
  ASSERT_EQ(initial, 16 * 8);
  EXPECT_EQ(initial_mass, double(initial) * 0.0625 * 0.0625);
  while (solver.time() < 6.0) solver.advance(6.0);
  const ObserverSample s = solver.observe();
  std::printf("%s: %d of %d particles left the domain by t = %.2f (mass %.8g + %.8g = %.8g)\n", std::string(TypeParam::test_label).c_str(),
              int(solver.left_domain_count()), int(initial), solver.time(), s.mass, solver.left_domain_mass(),
              s.mass + solver.left_domain_mass());
  EXPECT_GT(solver.left_domain_count(), initial / 2) << "most of the water falls off the ledge";
  EXPECT_EQ(solver.fluid_count() + solver.left_domain_count(), initial);
  EXPECT_EQ(s.mass + solver.left_domain_mass(), initial_mass);
}

TYPED_TEST(GeneralForm, LeavingWithStopDiagnoses) {
  const CaseDescription c = parse_case(ledge_case("leaving = \"stop\""), "ledge.toml");
  WeaklyCompressibleSolver<double, 2> solver(c, kind_of<TypeParam>());
  try {
    while (solver.time() < 6.0) solver.advance(6.0);
    FAIL() << "the water left the domain without a diagnostic";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("outside the domain"), std::string::npos) << e.what();
    EXPECT_EQ(solver.left_domain_count(), 0);
  }
}

// Bad general-form input: one line naming the file, the line and the key.
TEST(HostGeneralForm, BrokenCasesAreRefusedWithOneLine) {
  const std::string wedge = file_text(std::string(UNISPH_CASES_DIR) + "/dambreak_wedge_2d.toml");
  struct Broken {
    std::string text, expected;
  };
  const std::vector<Broken> parse_errors = {
      {replaced(wedge, "type = \"half_space\"", "type = \"cone\""), "key 'shape.type': must be \"box\""},
      {replaced(wedge, "shapes = [\"wedge_box\", \"slope\"]", "shapes = []"),
       "key 'shape.shapes': a intersection of 0 shapes: it needs at least 1"},
      {replaced(wedge, "shapes = [\"outer\", \"inside\"]", "shapes = [\"outer\"]"),
       "key 'shape.shapes': a difference of 1 shapes: it needs at least 2 (the first minus the others)"},
      {replaced(wedge, "shapes = [\"wedge_box\", \"slope\"]", "shapes = [\"wedge_box\", \"ramp\"]"),
       "key 'shape.shapes': 'ramp' is not the name of a shape defined above this one"},
      {replaced(wedge, "shape = \"column\"", "shape = \"colum\""), "key 'body.shape': 'colum' is not the name of a [[shape]]"},
      {replaced(wedge, "kind = \"fluid\"", "kind = \"gas\""), "key 'body.kind': must be \"fluid\" or \"wall\" (it is \"gas\")"},
      {replaced(wedge, "normal = [-0.5, 0.8660254037844386]", "normal = [0.0, 0.0]"), "key 'shape.normal': must not be the zero vector"},
      {replaced(wedge, "gravity = [0.0, -1.0]", "gravity = [0.0, 0.0]"), "key 'physics.gravity': must not be the zero vector"},
      {replaced(wedge, "[geometry]\ndx = 0.025", "[geometry]\ndx = 0.025\ntank = [1.0, 1.0]"),
       "key 'geometry.tank': the short form (geometry.tank, geometry.column) and [[body]] tables cannot be mixed"},
      {replaced(wedge, "upper = [5.466, 5.466]\n", "upper = [5.466, -0.2]\n"),
       "key 'domain.upper': must be above domain.lower along every axis (not along axis 1)"},
      {replaced(wedge, "name = \"wedge_box\"\ntype = \"box\"", "name = \"wedge_box\"\ntype = \"cylinder\""),
       "key 'shape.type': \"cylinder\" is a 3D shape; this case is 2D"},
      {replaced(wedge, "shape = \"column\"", "shape = \"column\"\nfill = \"smooth\""),
       "key 'body.fill': must be \"lattice\" or \"relaxed\" (it is \"smooth\")"},
      {replaced(wedge, "shape = \"column\"", "shape = \"column\"\nrelaxation_iterations = 100"),
       "key 'body.relaxation_iterations': is read only with body.fill = \"relaxed\""},
      {replaced(wedge, "shape = \"column\"", "shape = \"column\"\nfill = \"relaxed\"\nrelaxation_iterations = 0"),
       "key 'body.relaxation_iterations': must be 1 to 100000 (it is 0)"},
  };
  // Each broken text refused by `attempt` with one line naming the file, line and key.
  const auto expect_refused = [](const std::vector<Broken>& cases, const auto& attempt) {
    for (const Broken& b : cases) {
      try {
        attempt(b.text);
        ADD_FAILURE() << "accepted; expected: " << b.expected;
      } catch (const CaseFileError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(b.expected), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        EXPECT_EQ(what.rfind("dambreak_wedge_2d.toml:", 0), 0u) << what;
      }
    }
  };
  expect_refused(parse_errors, [](const std::string& text) { parse_case(text, "dambreak_wedge_2d.toml"); });
  // Errors found when the bodies are made.
  const std::vector<Broken> body_errors = {
      // A fluid shape thinner than the lattice.
      {replaced(wedge, "lower = [0.0, 0.0]\nupper = [2.0, 1.0]", "lower = [0.0, 0.0]\nupper = [2.0, 0.01]"),
       "key 'body.shape' (body 'water'): the fluid fills to no particle"},
      // A fluid outside the domain.
      {replaced(wedge, "lower = [0.0, 0.0]\nupper = [2.0, 1.0]", "lower = [0.0, 0.0]\nupper = [2.0, 1.0]\ntranslation = [8.0, 0.0]"),
       "key 'body.shape' (body 'water'): the fluid's shape 'column' reaches outside the domain"},
      // A wall outside the domain.
      {replaced(wedge, "lower = [3.766, -0.1]", "lower = [3.766, -0.1]\ntranslation = [0.0, 9.0]"),
       "key 'body.shape' (body 'wedge'): the wall has no particle within the domain"},
      // Fluid entirely inside a wall.
      {replaced(wedge, "lower = [0.0, 0.0]\nupper = [2.0, 1.0]", "lower = [3.9, 0.0]\nupper = [4.3, 0.05]"),
       "key 'body.shape' (body 'water'): every one of the fluid's"},
  };
  expect_refused(body_errors, [](const std::string& text) {
    WeaklyCompressibleSolver<double, 2> solver(parse_case(text, "dambreak_wedge_2d.toml"), PolicyKind::seq);
  });
}
