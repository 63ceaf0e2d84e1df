// Particle relaxation (issue 7), the checks on the longer cases (ctest label
// validation): the zero-order consistency error |Σ_j ∇W_ij V_j + G| h falls from the lattice by
// >= 100x in the mean, >= 30x at the 99th percentile and >= 10x at the largest; Σ_j W_ij V_j + S
// within ±3 % of the full lattice's at 95 % of the particles; no particle outside by more than
// 0.1 dx; count and ids kept; for the sphere the particles hold the mesh's volume within 1 %.
// These are the thresholds, not measured bounds: see docs/particle_generation.md for
// which of them the method meets.
#include <cstdio>
#include <string>

#include "relaxation_checks.hpp"
#include "support/policy_test.hpp"
#include "test_data.hpp"

namespace {
using namespace unisph;
using namespace unisph::testing;

template <int D, class P>
void relax_and_check(P policy, const std::string& file, Real dx, int iterations, bool check_volume) {
  RelaxationGeometry<D> g = load_relaxation_geometry<D>(policy, test_data("geometry/" + file), dx);
  std::unique_ptr<ParticleRelaxation<D>> relaxation = g.relaxation(policy, dx);
  const RelaxedSetState lattice = measure_state<D>(policy, *relaxation);
  RelaxationSettings settings;
  settings.iterations = iterations;
  relaxation->run(policy, settings);
  const RelaxedSetState relaxed = measure_state<D>(policy, *relaxation);
  std::printf("%s dx %g, %d iterations\n", file.c_str(), double(dx), iterations);
  print_state("lattice", lattice);
  print_state("relaxed", relaxed);
  std::printf("  reduction: mean %.1f  p99 %.1f  max %.1f\n", lattice.mean_error / relaxed.mean_error,
              lattice.p99_error / relaxed.p99_error, lattice.max_error / relaxed.max_error);
  EXPECT_GE(lattice.mean_error / relaxed.mean_error, 100.0);
  EXPECT_GE(lattice.p99_error / relaxed.p99_error, 30.0);
  EXPECT_GE(lattice.max_error / relaxed.max_error, 10.0);
  EXPECT_GE(relaxed.kernel_sum_within_3_percent, 0.95);
  EXPECT_LE(relaxed.largest_phi, 0.1 * double(dx));
  EXPECT_EQ(relaxed.particles, lattice.particles);
  EXPECT_TRUE(relaxed.ids_are_a_permutation);
  if (check_volume) {
    EXPECT_NEAR(relaxed.total_volume / g.enclosed, 1.0, 0.01);
  }
}

UNISPH_POLICY_TEST_SUITE(RelaxationValidation);

TYPED_TEST(RelaxationValidation, UnitSphereDx005) {
  relax_and_check<3>(this->policy, "trimesh_unit_sphere.stl", Real(0.05), 1500, true);
}
TYPED_TEST(RelaxationValidation, AnnulusDx005) {
  relax_and_check<2>(this->policy, "annulus.poly", Real(0.05), 2000, false);
}
TYPED_TEST(RelaxationValidation, PlateWithHolesDx01) {
  relax_and_check<2>(this->policy, "plate_with_holes.poly", Real(0.1), 1500, false);
}
TYPED_TEST(RelaxationValidation, TeapotDx028) {
  relax_and_check<3>(this->policy, "teapot.stl", Real(0.28), 1500, false);
}
// 3000 iterations: at 1500 the mean was 85.8x (par, session 4; 93.1x on the H100 in session 3)
// and still rising by about 7x per 100 iterations; 3000 gave 129.3x / 275.1x / 41.2x on par
// (docs/particle_generation.md).
TYPED_TEST(RelaxationValidation, TeapotDx014) {
  relax_and_check<3>(this->policy, "teapot.stl", Real(0.14), 3000, false);
}
TYPED_TEST(RelaxationValidation, SPHinXsysLettersDx004) {
  relax_and_check<3>(this->policy, "SPHinXsys.stl", Real(0.04), 1500, false);
}

}  // namespace
