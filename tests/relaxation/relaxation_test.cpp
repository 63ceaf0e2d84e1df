// Particle relaxation (issue 7) on every policy, the short cases that CI runs:
//   - the annulus (a 2D polygon with a hole) relaxed: the zero-order consistency error falls
//     from the lattice's, the kernel sums stay near the full lattice's, no particle ends
//     outside, count and ids kept, the particles hold the polygon's area; par and the GPU
//     reach seq's error and volume;
//   - the unit sphere (dx = 0.05): the seeded particles hold the mesh's divergence-theorem
//     volume; after 10 iterations par and the GPU give seq's positions.
// The reduction factors (100x mean, 30x p99, 10x max) are checked on the longer cases
// in relaxation_validation_test.cpp (label validation); the bounds here are what was measured,
// with a margin (docs/particle_generation.md).
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "relaxation_checks.hpp"
#include "support/policy_test.hpp"
#include "test_data.hpp"

namespace {
using namespace unisph;
using namespace unisph::testing;
constexpr bool single = sizeof(Real) == 4;

UNISPH_POLICY_TEST_SUITE(Relaxation);

struct Outcome {
  RelaxedSetState lattice, relaxed;
  double enclosed;
};

template <int D, class P>
Outcome relax(P policy, const std::string& file, Real dx, int iterations) {
  RelaxationGeometry<D> g = load_relaxation_geometry<D>(policy, test_data("geometry/" + file), dx);
  std::unique_ptr<ParticleRelaxation<D>> relaxation = g.relaxation(policy, dx);
  Outcome o;
  o.enclosed = g.enclosed;
  o.lattice = measure_state<D>(policy, *relaxation);
  RelaxationSettings settings;
  settings.iterations = iterations;
  relaxation->run(policy, settings);
  o.relaxed = measure_state<D>(policy, *relaxation);
  std::printf("%s dx %g, %d iterations\n", file.c_str(), double(dx), iterations);
  print_state("lattice", o.lattice);
  print_state("relaxed", o.relaxed);
  std::printf("  reduction: mean %.1f  p99 %.1f  max %.1f\n", o.lattice.mean_error / o.relaxed.mean_error,
              o.lattice.p99_error / o.relaxed.p99_error, o.lattice.max_error / o.relaxed.max_error);
  return o;
}

// Measured (double, seq and par, 600 iterations): mean 29.4x, p99 45.6x, max 37.0x, kernel sum
// within 3 % at 97.9 % of the particles, largest phi -5.5e-4 (all inside), area -0.19 %.
TYPED_TEST(Relaxation, AnnulusPolygonWithAHole) {
  const Real dx = Real(0.05);
  const Outcome o = relax<2>(this->policy, "annulus.poly", dx, 600);
  EXPECT_GE(o.lattice.mean_error / o.relaxed.mean_error, 20.0);
  EXPECT_GE(o.lattice.p99_error / o.relaxed.p99_error, 30.0);
  EXPECT_GE(o.lattice.max_error / o.relaxed.max_error, 20.0);
  EXPECT_GE(o.relaxed.kernel_sum_within_3_percent, 0.95);
  EXPECT_LE(o.relaxed.largest_phi, 0.1 * double(dx));
  EXPECT_EQ(o.relaxed.particles, o.lattice.particles);
  EXPECT_TRUE(o.relaxed.ids_are_a_permutation);
  EXPECT_NEAR(o.relaxed.total_volume / o.enclosed, 1.0, 0.01);
  if constexpr (!std::is_same_v<TypeParam, SequencedPolicy>) {
    // The issue: after the full run, residual and volume within 1 % of seq's.
    const Outcome reference = relax<2>(seq, "annulus.poly", dx, 600);
    EXPECT_NEAR(o.relaxed.mean_error / reference.relaxed.mean_error, 1.0, 0.01);
    EXPECT_NEAR(o.relaxed.total_volume / reference.relaxed.total_volume, 1.0, 0.01);
  }
}

// The lattice inside the sphere holds the mesh's own volume (4.1527, divergence theorem):
// measured -0.04 % at dx = 0.05.
TYPED_TEST(Relaxation, SphereLatticeHoldsTheMeshVolume) {
  const Real dx = Real(0.05);
  RelaxationGeometry<3> g = load_relaxation_geometry<3>(this->policy, test_data("geometry/trimesh_unit_sphere.stl"), dx);
  std::unique_ptr<ParticleRelaxation<3>> relaxation = g.relaxation(this->policy, dx);
  const RelaxedSetState s = measure_state<3>(this->policy, *relaxation);
  std::printf("sphere: %zu particles, volume %.6f, mesh %.6f\n", s.particles, s.total_volume, g.enclosed);
  EXPECT_NEAR(s.total_volume / g.enclosed, 1.0, 0.01);
  EXPECT_LE(s.largest_phi, 0.1 * double(dx));
  EXPECT_TRUE(s.ids_are_a_permutation);
}

// Positions by id after 10 iterations (sphere, dx = 0.05): the same as seq's within 1e-10
// relative in double (par forms the same sums in the same order: equal bit for bit here).
template <class P>
std::map<std::uint64_t, Vec<Real, 3>> positions_after_ten(P policy) {
  const Real dx = Real(0.05);
  RelaxationGeometry<3> g = load_relaxation_geometry<3>(policy, test_data("geometry/trimesh_unit_sphere.stl"), dx);
  std::unique_ptr<ParticleRelaxation<3>> relaxation = g.relaxation(policy, dx);
  RelaxationSettings settings;
  settings.iterations = 10;
  relaxation->run(policy, settings);
  const std::vector<Vec<Real, 3>> x = relaxation->positions().to_vector();
  const std::vector<std::uint64_t> ids = relaxation->body().particles().ids().to_vector();
  std::map<std::uint64_t, Vec<Real, 3>> by_id;
  for (std::size_t i = 0; i < x.size(); ++i) by_id[ids[i]] = x[i];
  return by_id;
}

TYPED_TEST(Relaxation, SameAsSeqAfterTenIterations) {
  const auto mine = positions_after_ten(this->policy);
  const auto reference = positions_after_ten(seq);
  ASSERT_EQ(mine.size(), reference.size());
  const double tolerance = single ? 1e-5 : 1e-10;  // relative to the sphere's radius, 1
  double worst = 0;
  for (const auto& [id, x] : reference) {
    const auto it = mine.find(id);
    ASSERT_NE(it, mine.end()) << "particle id " << id << " missing";
    worst = std::max(worst, double(norm(it->second - x)));
  }
  std::printf("largest position difference from seq after 10 iterations: %.3e\n", worst);
  EXPECT_LE(worst, tolerance);
}

}  // namespace
