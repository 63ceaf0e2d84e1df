// A curved container from a triangle mesh (cases/spherical_tank_3d.toml): water at rest in a
// half-filled spherical tank whose wall is everything outside the unit sphere of an STL file,
// through the general form, on every policy. After the settling stage and 10 time units:
//  * no water particle lies more than 0.25 dx inside the wall (the wall shape's own signed
//    distance, through the mesh's level set, at every particle);
//  * kinetic energy below 1e-3 of the potential energy (taken above the tank's bottom);
//  * the mass is exact: every particle's mass, summed in the order of the ids, is the initial sum.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
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
double mass_by_id(Body<double, 3>& body) {
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
