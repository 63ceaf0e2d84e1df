// Particle relaxation (issue 7) on every policy, the short cases that CI runs:
//   - the annulus (a 2D polygon with a hole) relaxed: the zero-order consistency error falls
//     from the lattice's, the kernel sums stay near the full lattice's, no particle ends
//     outside, count and ids kept, the particles hold the polygon's area; par and the GPU
//     give seq's run bit for bit (positions, residuals, history, volume);
//   - the unit sphere (dx = 0.05): the seeded particles hold the mesh's divergence-theorem
//     volume; after 10 iterations par and the GPU give seq's positions bit for bit.
// The reduction factors (100x mean, 30x p99, 10x max) are asserted here on the annulus
// and on the longer cases in relaxation_validation_test.cpp (label validation)
// (docs/particle_generation.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "relaxation_checks.hpp"
#include "support/policy_test.hpp"
#include "test_data.hpp"

namespace {
using namespace unisph;
using namespace unisph::testing;

UNISPH_POLICY_TEST_SUITE(Relaxation);

struct Outcome {
  RelaxedSetState lattice, relaxed;
  double enclosed;
  std::vector<Vec<Real, 2>> positions;  // by particle id
  std::vector<Real> residual_norms;     // |a_i| by particle id
  std::vector<RelaxationRecord> history;
};

template <int D>
std::vector<Vec<Real, D>> by_id(ParticleRelaxation<D>& relaxation, const std::vector<Vec<Real, D>>& values) {
  const std::vector<std::uint64_t> ids = relaxation.body().particles().ids().to_vector();
  std::vector<Vec<Real, D>> sorted(values.size());
  for (std::size_t i = 0; i < ids.size(); ++i) sorted[ids[i]] = values[i];
  return sorted;
}

template <int D, class P>
Outcome relax(P policy, const std::string& file, Real dx, int iterations) {
  RelaxationGeometry<D> g = load_relaxation_geometry<D>(policy, test_data("geometry/" + file), dx);
  std::unique_ptr<ParticleRelaxation<D>> relaxation = g.relaxation(policy, dx);
  Outcome o;
  o.enclosed = g.enclosed;
  o.lattice = measure_state<D>(policy, *relaxation);
  RelaxationSettings settings;
  settings.iterations = iterations;
  o.history = relaxation->run(policy, settings);
  o.relaxed = measure_state<D>(policy, *relaxation);
  if constexpr (D == 2) {
    o.positions = by_id<D>(*relaxation, relaxation->positions().to_vector());
    for (const Vec<Real, D>& a : by_id<D>(*relaxation, relaxation->residuals().to_vector()))
      o.residual_norms.push_back(norm(a));
  }
  std::printf("%s dx %g, %d iterations\n", file.c_str(), double(dx), iterations);
  print_state("lattice", o.lattice);
  print_state("relaxed", o.relaxed);
  std::printf("  reduction: mean %.1f  p99 %.1f  max %.1f\n", o.lattice.mean_error / o.relaxed.mean_error,
              o.lattice.p99_error / o.relaxed.p99_error, o.lattice.max_error / o.relaxed.max_error);
  return o;
}

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

// Measured (double, seq, par and the GPU alike, 1000 iterations: FIRE, its quench from iteration
// 400, plain descent from 900): mean 363.8x, p99 380.9x, max 165.1x, kernel sum within 3 % at
// 100 % of the particles, largest phi below 0 (all inside), area unchanged; float 709.5x,
// 697.3x, 989.8x. Asserted: the factors (100x, 30x, 10x). (With the
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
    // The issue: after the full run, residual and volume within 1 % of seq's. Every policy runs
    // the same arithmetic (no contraction, deterministic_reduce for FIRE's and the norms' sums,
    // neighbours in ascending j), so the trajectory is seq's bit for bit, in double and float
    // (docs/particle_generation.md, "The same bits on every policy"); asserted, and the largest
    // differences printed.
    const Outcome reference = relax<2>(seq, "annulus.poly", dx, annulus_iterations);
    ASSERT_EQ(o.positions.size(), reference.positions.size());
    double position_difference = 0, residual_difference = 0;
    std::size_t different_positions = 0, different_residuals = 0;
    for (std::size_t i = 0; i < o.positions.size(); ++i) {
      position_difference = std::max(position_difference, double(norm(o.positions[i] - reference.positions[i])));
      residual_difference =
          std::max(residual_difference, double(std::abs(o.residual_norms[i] - reference.residual_norms[i])));
      different_positions += !same_bits(o.positions[i], reference.positions[i]);
      different_residuals += !same_bits(o.residual_norms[i], reference.residual_norms[i]);
    }
    std::size_t different_records = 0;
    for (std::size_t k = 0; k < std::min(o.history.size(), reference.history.size()); ++k)
      different_records += !same_bits(o.history[k].mean_error, reference.history[k].mean_error) ||
                           !same_bits(o.history[k].max_error, reference.history[k].max_error) ||
                           !same_bits(o.history[k].step, reference.history[k].step);
    std::printf("  against seq: final mean error %.17g / %.17g, volume %.17g / %.17g; largest position difference "
                "%.3e, residual %.3e; %zu positions, %zu residuals, %zu history rows not bit-identical\n",
                o.relaxed.mean_error, reference.relaxed.mean_error, o.relaxed.total_volume,
                reference.relaxed.total_volume, position_difference, residual_difference, different_positions,
                different_residuals, different_records);
    EXPECT_NEAR(o.relaxed.mean_error / reference.relaxed.mean_error, 1.0, 0.01);  // the bound
    EXPECT_NEAR(o.relaxed.total_volume / reference.relaxed.total_volume, 1.0, 0.01);
    EXPECT_EQ(o.history.size(), reference.history.size());
    EXPECT_EQ(different_records, 0u);
    EXPECT_EQ(different_positions, 0u);
    EXPECT_EQ(different_residuals, 0u);
    EXPECT_TRUE(same_bits(o.relaxed.mean_error, reference.relaxed.mean_error));
    EXPECT_TRUE(same_bits(o.relaxed.total_volume, reference.relaxed.total_volume));
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

// Positions by id after 10 iterations (sphere, dx = 0.05): the issue asks for seq's within 1e-10
// relative in double; every policy gives seq's bits, in double and in float (the level set, the
// seeding and the relaxation built on the device without contraction, the global sums by
// deterministic_reduce).
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
  const double tolerance = 1e-10;  // relative to the sphere's radius, 1
  double worst = 0;
  std::size_t different = 0;
  for (const auto& [id, x] : reference) {
    const auto it = mine.find(id);
    ASSERT_NE(it, mine.end()) << "particle id " << id << " missing";
    worst = std::max(worst, double(norm(it->second - x)));
    different += !same_bits(it->second, x);
  }
  std::printf("largest position difference from seq after 10 iterations: %.3e (%zu of %zu not bit-identical)\n",
              worst, different, reference.size());
  EXPECT_LE(worst, tolerance);
  EXPECT_EQ(different, 0u);
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
