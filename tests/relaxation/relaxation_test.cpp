// Particle relaxation (issue 7) on every policy, the short cases that CI runs:
//   - the annulus (a 2D polygon with a hole) relaxed: the zero-order consistency error falls
//     from the lattice's, the kernel sums stay near the full lattice's, no particle ends
//     outside, count and ids kept, the particles hold the polygon's area; par and the GPU
//     reach seq's error and volume;
//   - the unit sphere (dx = 0.05): the seeded particles hold the mesh's divergence-theorem
//     volume; after 10 iterations par and the GPU give seq's positions.
// The reduction factors (100x mean, 30x p99, 10x max) are asserted here on the annulus
// and on the longer cases in relaxation_validation_test.cpp (label validation)
// (docs/particle_generation.md).
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

// Measured (double, seq and par, 1000 iterations: FIRE, its quench from iteration 400, plain
// descent from 900): mean 372.3x, p99 383.3x, max 173.1x, kernel sum within 3 % at 100 % of the particles, largest phi
// below 0 (all inside), area unchanged. Asserted: the factors (100x, 30x, 10x). (With the
// sub-cell kernel integrals, 600 iterations gave 101.6x in the mean, too close to the bound for a
// trajectory that parts from seq's on round-off: docs/particle_generation.md.)
constexpr int annulus_iterations = 1000;
TYPED_TEST(Relaxation, AnnulusPolygonWithAHole) {
  const Real dx = Real(0.05);
  const Outcome o = relax<2>(this->policy, "annulus.poly", dx, annulus_iterations);
  EXPECT_GE(o.lattice.mean_error / o.relaxed.mean_error, 100.0);
  EXPECT_GE(o.lattice.p99_error / o.relaxed.p99_error, 30.0);
  EXPECT_GE(o.lattice.max_error / o.relaxed.max_error, 10.0);
  EXPECT_GE(o.relaxed.kernel_sum_within_3_percent, 0.95);
  EXPECT_LE(o.relaxed.largest_phi, 0.1 * double(dx));
  EXPECT_EQ(o.relaxed.particles, o.lattice.particles);
  EXPECT_TRUE(o.relaxed.ids_are_a_permutation);
  EXPECT_NEAR(o.relaxed.total_volume / o.enclosed, 1.0, 0.01);
  if constexpr (!std::is_same_v<TypeParam, SequencedPolicy>) {
    // The issue: after the full run, residual and volume within 1 % of seq's. par follows seq's
    // arithmetic and meets it. The GPU does not (FMA contraction and its reduction order part
    // the trajectory from seq's at round-off, and this energy has many minima): on an H100 its
    // final mean error was 0.614 of seq's, and start positions nudged by 5e-16 to 5e-14 dx moved
    // seq's own final mean by up to 35 % (docs/particle_generation.md, "Final descent, and how
    // reproducible the final error is"). So the GPU is held to that measured spread, not to the
    // issue's 1 %, which stays reported as not met.
    const Outcome reference = relax<2>(seq, "annulus.poly", dx, annulus_iterations);
    const double mean_tolerance = std::is_same_v<TypeParam, ParallelPolicy> ? 0.01 : 0.5;
    std::printf("  final mean error against seq's: %.4f\n", o.relaxed.mean_error / reference.relaxed.mean_error);
    EXPECT_NEAR(o.relaxed.mean_error / reference.relaxed.mean_error, 1.0, mean_tolerance);
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
  // The bound is for double. In float, par's sums differ from seq's in the last bits and
  // FIRE's quench (a per-particle sign test of a.v, from the 4th of 10 iterations) stops a
  // particle whose a.v is within round-off of zero in one run and not in the other: measured
  // 4.0e-3 of the radius apart after 10 iterations (asan preset, float).
  if (single) GTEST_SKIP() << "compared in double only (FIRE's quench decides per particle on a sign)";
  const auto mine = positions_after_ten(this->policy);
  const auto reference = positions_after_ten(seq);
  ASSERT_EQ(mine.size(), reference.size());
  const double tolerance = 1e-10;  // relative to the sphere's radius, 1
  double worst = 0;
  for (const auto& [id, x] : reference) {
    const auto it = mine.find(id);
    ASSERT_NE(it, mine.end()) << "particle id " << id << " missing";
    worst = std::max(worst, double(norm(it->second - x)));
  }
  std::printf("largest position difference from seq after 10 iterations: %.3e\n", worst);
  EXPECT_LE(worst, tolerance);
}

// A polygon with holes (plate_with_holes.poly: two holes, an island in one, a separate
// triangle), seeded by the level set's own sign (LevelSetSide) inside the body and around it in
// a box, then relaxed 30 iterations: inside, no particle lies in a hole or outside farther than
// 0.1 dx from the material (the polygons' even-odd rule); around, none lies in the material
// farther than 0.1 dx from its edge and the holes are filled. Before the level set gave enclosed
// regions the side of their cells' vote, the middle of a hole was inside (phi < 0) and took
// particles.
bool inside_polygons(const PolygonSet& polygons, const Vec<double, 2>& p, double& distance) {
  double best = 1e300;
  bool inside = false;
  for (std::size_t loop = 0; loop + 1 < polygons.loop_start.size(); ++loop) {
    const std::uint32_t begin = polygons.loop_start[loop], end = polygons.loop_start[loop + 1];
    for (std::uint32_t i = begin; i < end; ++i) {
      const Vec<double, 2> a = polygons.vertices[i], c = polygons.vertices[i + 1 < end ? i + 1 : begin];
      const Vec<double, 2> e = c - a;
      const double t = std::min(1.0, std::max(0.0, dot(p - a, e) / dot(e, e)));
      best = std::min(best, squared_norm(p - (a + e * t)));
      if ((a[1] > p[1]) != (c[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) / (c[1] - a[1]) * e[0]) inside = !inside;
    }
  }
  distance = std::sqrt(best);
  return inside;
}

TYPED_TEST(Relaxation, PolygonHolesGetNoParticles) {
  const Real dx = Real(0.1);
  RelaxationGeometry<2> g = load_relaxation_geometry<2>(this->policy, test_data("geometry/plate_with_holes.poly"), dx);
  const PolygonSet polygons = read_polygons(test_data("geometry/plate_with_holes.poly")).polygons;
  for (const SeedRegion region : {SeedRegion::inside, SeedRegion::outside}) {
    const bool around = region == SeedRegion::outside;
    const Box<Real, 2> box = around ? Box<Real, 2>{Vec<Real, 2>{{-0.3, -0.3}}, Vec<Real, 2>{{15.3, 10.3}}} : g.box;
    ParticleRelaxation<2> relaxation(this->policy, *g.level_set, box, region, dx);
    RelaxationSettings settings;
    settings.iterations = 30;
    relaxation.run(this->policy, settings);
    const std::vector<Vec<Real, 2>> x = relaxation.positions().to_vector();
    Index wrong = 0, in_hole_1 = 0;
    for (const auto& p : x) {
      double distance = 0;
      const bool inside = inside_polygons(polygons, Vec<double, 2>{{double(p[0]), double(p[1])}}, distance);
      wrong += inside == around && distance > 0.1 * double(dx);
      in_hole_1 += p[0] > Real(1.5) && p[0] < Real(3.5) && p[1] > Real(1.5) && p[1] < Real(3.5);
    }
    std::printf("plate with holes, %s: %zu particles, %zu on the wrong side, %zu in the middle of hole 1\n",
                around ? "around" : "inside", x.size(), std::size_t(wrong), std::size_t(in_hole_1));
    EXPECT_GT(x.size(), 1000u);
    EXPECT_EQ(wrong, 0u);
    // the 2 x 2 middle of hole 1 holds 400 lattice points of spacing 0.1
    if (around) {
      EXPECT_GT(in_hole_1, 300u);
    } else {
      EXPECT_EQ(in_hole_1, 0u);
    }
  }
}

}  // namespace
