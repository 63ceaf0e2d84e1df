// A curved container from a triangle mesh (cases/spherical_tank_3d.toml): water at rest in a
// half-filled spherical tank whose wall is everything outside the unit sphere of an STL file,
// through the general form, on every policy. After the settling stage and 10 time units:
//  * no water particle lies more than 0.25 dx inside the wall (the wall shape's own signed
//    distance, through the mesh's level set, at every particle);
//  * kinetic energy below 1e-3 of the potential energy (taken above the tank's bottom);
//  * the mass is exact: every particle's mass, summed in the order of the ids, is the initial sum.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "support/policy_test.hpp"
#include "unisph/solver/body_particles.hpp"
#include "unisph/solver/case_file.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"

using namespace unisph;
using namespace unisph::sph;
using unisph::testing::kind_of;

namespace {

// The sum of every particle's mass in the order of the ids (independent of the particles' order).
template <int D>
double mass_by_id(Body<double, D>& body) {
  const std::vector<std::uint64_t> ids = body.particles().ids().to_vector();
  const std::vector<double> mass = body.particles().template variable<double>("Mass").to_vector();
  std::vector<double> by_id(mass.size());
  for (std::size_t i = 0; i < ids.size(); ++i) by_id[ids[i] - body.particles().first_id()] = mass[i];
  double sum = 0;
  for (double m : by_id) sum += m;
  return sum;
}

}  // namespace

UNISPH_POLICY_TEST_SUITE(CurvedContainer);

TYPED_TEST(CurvedContainer, HalfFilledSphericalTankFromAMeshStaysAtRest) {
  const CaseDescription c = read_case_file(std::string(UNISPH_CASES_DIR) + "/spherical_tank_3d.toml");
  WeaklyCompressibleSolver<double, 3> solver(c, kind_of<TypeParam>());
  const double initial_mass = mass_by_id(solver.fluid_body());
  while (solver.time() < c.end_time * (1 - 1e-12)) solver.advance(c.end_time);
  const ObserverSample s = solver.observe();

  // The wall's own shape (the mesh's level set), evaluated at every water particle.
  ShapeBuilder<3> shapes(c);
  shape::CompiledShape<3> wall(shapes.get(seq, "tank"));
  const shape::ShapeView<3> solid = wall.view(seq);
  double deepest = -1e9;
  for (const Vec<double, 3>& x : solver.fluid_body().positions().to_vector())
    deepest = std::max(deepest, -double(solid.signed_distance(Vec<Real, 3>{{Real(x[0]), Real(x[1]), Real(x[2])}})));
  const double dx = c.dx;
  std::printf("%s: %d water and %d wall particles; after %.0f settling + %.0f time units: deepest water particle %.3f dx "
              "inside the wall (bound 0.25; < 0: none inside), kinetic / potential energy %.2e (bound 1e-3), mass %.17g / %.17g\n",
              std::string(TypeParam::test_label).c_str(), int(solver.fluid_count()), int(solver.wall_count()), c.settling_time,
              solver.time(), deepest / dx, s.kinetic_energy / s.potential_energy, mass_by_id(solver.fluid_body()), initial_mass);
  EXPECT_LT(deepest, 0.25 * dx);
  EXPECT_GT(s.potential_energy, 0.0);
  EXPECT_LT(s.kinetic_energy, 1e-3 * s.potential_energy);
  EXPECT_EQ(mass_by_id(solver.fluid_body()), initial_mass);
  EXPECT_EQ(solver.left_domain_count(), 0);
}

// Body-fitted particles (fill = "relaxed", cases/circular_tank_relaxed_2d.toml) against the same
// tank on the lattice: a half-filled circular tank of radius R = 1, dx = R / 20.
//  * made: the water's particles hold the half circle's area (pi / 2) / dx^2 within 1 % (the
//    lattice, filled by whole cells less the points within dx / 2 of the wall, holds 6 % less);
//    every wall particle lies in the wall's band (0 to 4 dx deep); the water lines the circle:
//    its particles within dx of it form a layer as full as the wall's first layer on the same
//    arc, at a gap of 0.3 to 0.6 dx with a spread (standard deviation) below 0.15 dx and below
//    half the lattice's first layer's (its points lie 0.5 to 1.5 dx from the circle);
//  * run: after the settling and 10 time units, as the spherical tank: no water particle more
//    than 0.25 dx inside the wall, kinetic below 1e-3 of potential energy, mass exact.
TYPED_TEST(CurvedContainer, RelaxedCircularTankLinesTheWall) {
  const CaseDescription relaxed = read_case_file(std::string(UNISPH_CASES_DIR) + "/circular_tank_relaxed_2d.toml");
  CaseDescription lattice = relaxed;
  for (BodyDescription& b : lattice.bodies) b.fill = "lattice";
  const double dx = relaxed.dx;
  ShapeBuilder<2> shapes(relaxed);
  shape::CompiledShape<2> wall(shapes.get(seq, "tank"));
  const shape::ShapeView<2> solid = wall.view(seq);
  const auto depth = [&](const Vec<double, 2>& x) { return -double(solid.signed_distance(Vec<Real, 2>{{Real(x[0]), Real(x[1])}})); };

  const TankParticles<double, 2> made = make_body_particles<double, 2>(this->policy, relaxed);
  const TankParticles<double, 2> on_lattice = make_body_particles<double, 2>(this->policy, lattice);
  // Below y = 0.9 (clear of the free surface's ends): the water's and the wall's first layers.
  double sum = 0, sum2 = 0;
  int water_layer = 0, wall_layer = 0;
  for (const Vec<double, 2>& x : made.fluid) {
    const double gap = -depth(x);
    if (gap < dx && x[1] < 0.9) sum += gap, sum2 += gap * gap, ++water_layer;
  }
  double shallowest = 1e9, deepest_wall = -1e9;
  for (const Vec<double, 2>& x : made.wall) {
    shallowest = std::min(shallowest, depth(x));
    deepest_wall = std::max(deepest_wall, depth(x));
    if (depth(x) < dx && x[1] < 0.9) ++wall_layer;
  }
  const double mean = sum / water_layer, spread = std::sqrt(std::max(0.0, sum2 / water_layer - mean * mean));
  // The lattice's first layer: its points lie 0.5 to 1.5 dx from the circle (those within dx / 2 were removed).
  double lattice_sum = 0, lattice_sum2 = 0;
  int lattice_layer = 0;
  for (const Vec<double, 2>& x : on_lattice.fluid) {
    const double gap = -depth(x);
    if (gap < 1.5 * dx && x[1] < 0.9) lattice_sum += gap, lattice_sum2 += gap * gap, ++lattice_layer;
  }
  const double lattice_mean = lattice_sum / lattice_layer;
  const double lattice_spread = std::sqrt(std::max(0.0, lattice_sum2 / lattice_layer - lattice_mean * lattice_mean));
  const double area = std::numbers::pi / 2 / (dx * dx);
  std::printf("%s: relaxed: %d water particles (half circle: %.1f; lattice: %d), %d wall particles, %.3f .. %.3f dx deep; "
              "water within dx of the circle: %d particles (wall's first layer: %d) at %.3f dx, spread %.3f dx (lattice: %d "
              "within 1.5 dx at %.3f dx, spread %.3f dx); relaxation error |sum grad W V + G| h mean %.2e (wall), %.2e (water)\n",
              std::string(TypeParam::test_label).c_str(), int(made.fluid.size()), area, int(on_lattice.fluid.size()),
              int(made.wall.size()), shallowest / dx, deepest_wall / dx, water_layer, wall_layer, mean / dx, spread / dx,
              lattice_layer, lattice_mean / dx, lattice_spread / dx, made.relaxed.at(0).mean_error, made.relaxed.at(1).mean_error);
  ASSERT_EQ(made.relaxed.size(), 2u);
  EXPECT_NEAR(double(made.fluid.size()), area, 0.01 * area);
  EXPECT_GT(shallowest, 0.0);
  EXPECT_LT(deepest_wall, 4.0 * dx);
  EXPECT_GE(water_layer, int(0.9 * wall_layer));
  EXPECT_GT(mean, 0.3 * dx);
  EXPECT_LT(mean, 0.6 * dx);
  EXPECT_LT(spread, 0.15 * dx);
  EXPECT_LT(spread, lattice_spread / 2);

  WeaklyCompressibleSolver<double, 2> solver(relaxed, kind_of<TypeParam>());
  ASSERT_EQ(solver.relaxed_bodies().size(), 2u);
  const double initial_mass = mass_by_id(solver.fluid_body());
  while (solver.time() < relaxed.end_time * (1 - 1e-12)) solver.advance(relaxed.end_time);
  const ObserverSample s = solver.observe();
  double deepest = -1e9;
  for (const Vec<double, 2>& x : solver.fluid_body().positions().to_vector()) deepest = std::max(deepest, depth(x));
  std::printf("%s: after %.0f settling + %.0f time units: deepest water particle %.3f dx inside the wall (bound 0.25), "
              "kinetic / potential energy %.2e (bound 1e-3)\n",
              std::string(TypeParam::test_label).c_str(), relaxed.settling_time, solver.time(), deepest / dx,
              s.kinetic_energy / s.potential_energy);
  EXPECT_LT(deepest, 0.25 * dx);
  EXPECT_GT(s.potential_energy, 0.0);
  EXPECT_LT(s.kinetic_energy, 1e-3 * s.potential_energy);
  EXPECT_EQ(mass_by_id(solver.fluid_body()), initial_mass);
}
