// Particle relaxation (issue 7) on every policy: the zero-order consistency error falls from the
// lattice by the factors the issue asks for, the kernel sums stay near the lattice's, no particle
// ends outside, the count and the ids are kept, the sphere's particles hold the mesh's volume,
// and par and the GPU give seq's result.
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <string>
#include <vector>

#include "relaxation_checks.hpp"
#include "support/policy_test.hpp"
#include "test_data.hpp"

namespace {
using namespace unisph;
using namespace unisph::testing;

struct CaseSpec {
  std::string file;
  Real dx;
  int iterations;
  double volume_tolerance;  // relative, against the mesh's enclosed volume; <= 0: not checked
};

template <int D, class P>
void relax_and_check(P policy, const CaseSpec& spec) {
  RelaxationGeometry<D> g = load_relaxation_geometry<D>(policy, test_data("geometry/" + spec.file), spec.dx);
  std::unique_ptr<ParticleRelaxation<D>> owner = g.relaxation(policy, spec.dx);
  ParticleRelaxation<D>& relaxation = *owner;
  const RelaxedSetState lattice = measure_state<D>(policy, relaxation);
  RelaxationSettings settings;
  settings.iterations = spec.iterations;
  if (const char* e = std::getenv("RB")) settings.step_coefficient = Real(std::atof(e));
  if (const char* e = std::getenv("RM")) settings.largest_move = Real(std::atof(e));
  if (const char* e = std::getenv("RU")) settings.momentum = Real(std::atof(e));
  if (const char* e = std::getenv("RI")) settings.iterations = std::atoi(e);
  relaxation.run(policy, settings, [](const RelaxationRecord& r) {
    if (r.iteration % 50 == 0) std::printf("    %d mean %.3e max %.3e step %.3e\n", r.iteration, double(r.mean_error), double(r.max_error), double(r.step));
  });
  const RelaxedSetState relaxed = measure_state<D>(policy, relaxation);
  std::printf("%s dx %g, %d iterations\n", spec.file.c_str(), double(spec.dx), spec.iterations);
  print_state("lattice", lattice);
  print_state("relaxed", relaxed);
  std::printf("  reduction: mean %.1f  p99 %.1f  max %.1f\n", lattice.mean_error / relaxed.mean_error,
              lattice.p99_error / relaxed.p99_error, lattice.max_error / relaxed.max_error);
  EXPECT_GE(lattice.mean_error / relaxed.mean_error, 100.0);
  EXPECT_GE(lattice.p99_error / relaxed.p99_error, 30.0);
  EXPECT_GE(lattice.max_error / relaxed.max_error, 10.0);
  EXPECT_GE(relaxed.kernel_sum_within_3_percent, 0.95);
  EXPECT_LE(relaxed.largest_phi, 0.1 * double(spec.dx));
  EXPECT_EQ(relaxed.particles, lattice.particles);
  EXPECT_TRUE(relaxed.ids_are_a_permutation);
  if (spec.volume_tolerance > 0) {
    std::printf("  volume %.6f, enclosed %.6f, relative difference %.2e\n", relaxed.total_volume, g.enclosed,
                relaxed.total_volume / g.enclosed - 1);
    EXPECT_NEAR(relaxed.total_volume / g.enclosed, 1.0, spec.volume_tolerance);
  }
}

UNISPH_POLICY_TEST_SUITE(Relaxation);

TYPED_TEST(Relaxation, UnitSphereAtDx005) {
  relax_and_check<3>(this->policy, {"trimesh_unit_sphere.stl", Real(0.05), 300, 0.01});
}

TYPED_TEST(Relaxation, PlateWithHolesPolygon) {
  relax_and_check<2>(this->policy, {"plate_with_holes.poly", Real(0.1), 300, 0.0});
}

}  // namespace
