// A 2D piston wave flume (issue 22), in units of the depth d, g and rho0:
//  * policies agree: 200 advection steps of a short flume with a moving piston on seq, par and
//    the GPU within 1e-9 relative (double), the same neighbour search on each;
//  * validation (label `validation`, DISABLED_ in the quick entries; long: run it on the GPU): a
//    flume 34 d long, dx = d/100, a piston driven by Biesel's first-order transfer function for
//    waves of height H = 0.1 d (H/L = 0.016, 10 particles per height) at k d = 1, ramped over two
//    periods; a gauge 2.5 wavelengths from the paddle; over the five periods after the ramp's
//    tail passed it (and before anything reflected from the far end returns) the wave height
//    (twice the amplitude of the least-squares sinusoid) within 10 % of H and the period (the
//    best-fitting one) within 1 % of the paddle's.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "support/by_id.hpp"
#include "support/policy_test.hpp"
#include "unisph/motion/linear_waves.hpp"
#include "unisph/motion/wave_analysis.hpp"
#include "unisph/solver/case_file.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"

using namespace unisph;
using namespace unisph::sph;
using unisph::testing::by_id;
using unisph::testing::kind_of;

namespace {

// Depth 1; the water [0, length] x [0, 1]; the piston a plate 4 dx thick behind x = 0 moving by
// stroke/2 sin(2 pi t / period) ramped over two periods, reaching 4 dx into the floor (its
// particles overlap the floor's there: a piston that ends at the floor's surface leaves a path
// under it, along which water escaped behind the paddle); the floor under everything, a wall at
// the far end; a gauge at `gauge_x` (bottom 0.5, top 1.5).
std::string flume_case(double dx, double length, double stroke, double period, std::vector<double> gauge_x, double end,
                       double settling) {
  const double e = 4 * dx;
  std::ostringstream s;
  s.precision(17);
  s << "[case]\nname = \"piston_flume_2d\"\ndimension = 2\n[geometry]\ndx = " << dx << "\n"
    << "[domain]\nlower = [" << -1.0 << ", " << -e << "]\nupper = [" << length + e << ", 1.6]\nleaving = \"stop\"\n"
    << "[[shape]]\nname = \"floor\"\ntype = \"box\"\nlower = [-1.5, " << -2 * e << "]\nupper = [" << length + 2 * e << ", 0.0]\n"
    << "[[shape]]\nname = \"end\"\ntype = \"box\"\nlower = [" << length << ", 0.0]\nupper = [" << length + 2 * e << ", 2.0]\n"
    << "[[shape]]\nname = \"piston\"\ntype = \"box\"\nlower = [" << -e << ", " << -e << "]\nupper = [0.0, 1.5]\n"
    << "[[shape]]\nname = \"water\"\ntype = \"box\"\nlower = [0.0, 0.0]\nupper = [" << length << ", 1.0]\n"
    << "[[body]]\nname = \"floor\"\nkind = \"wall\"\nshape = \"floor\"\n"
    << "[[body]]\nname = \"end\"\nkind = \"wall\"\nshape = \"end\"\n"
    << "[[body]]\nname = \"piston\"\nkind = \"wall\"\nshape = \"piston\"\n"
    << "[body.translation]\nlaw = \"sinusoid\"\ndirection = [1.0, 0.0]\namplitude = " << stroke / 2 << "\nperiod = " << period
    << "\nramp_periods = 2\n"
    << "[[body]]\nname = \"water\"\nkind = \"fluid\"\nshape = \"water\"\n"
    << "[fluid]\ndensity = 1.0\nreference_velocity = 1.0\nsound_speed = 10.0\ncontinuity_dissipation = true\n"
    << "[physics]\ngravity = [0.0, -1.0]\n[initial]\nstate = \"hydrostatic\"\nfree_surface = 1.0\n"
    << (settling > 0 ? "settling_time = " + std::to_string(settling) + "\nsettling_damping = 1.0\n" : std::string())
    << "[time]\nend = " << end << "\noutput_interval = 1.0\n";
  for (std::size_t g = 0; g < gauge_x.size(); ++g)
    s << "[[gauge]]\nname = \"wave" << g << "\"\nposition = [" << gauge_x[g] << ", 0.0]\nbottom = 0.5\ntop = 1.5\n";
  return s.str();
}

}  // namespace

UNISPH_POLICY_TEST_SUITE(WaveFlume);

// 200 advection steps on Policy against seq; `corrected`: with fluid.kernel_gradient_correction;
// `shifting`: fluid.particle_shifting.
template <class Policy>
void expect_policies_agree_on_a_short_piston_flume(bool corrected, double shifting = 0, double smoothing_length_ratio = 1.3) {
  // With a velocity probe at mid-depth, 1 from the paddle ([[velocity_probe]]), and a damping zone
  // from 1.5 to the far wall that the wave reaches within the run ([damping_zone]).
  CaseDescription c = parse_case(flume_case(0.05, 4.0, 0.1, 2.0, {2.0}, 10.0, 0.0) +
                                     "[[velocity_probe]]\nname = \"mid\"\nposition = [1.0, 0.5]\n"
                                     "[damping_zone]\ndirection = [1.0, 0.0]\nstart = 1.5\nend = 4.0\nstrength = 2.0\n",
                                 "piston_flume_2d.toml");
  c.neighbor_search = "stored";  // the same method on every policy
  c.kernel_gradient_correction = corrected;
  c.particle_shifting = shifting;
  c.smoothing_length_ratio = smoothing_length_ratio;
  WeaklyCompressibleSolver<double, 2> reference(c, PolicyKind::seq);
  WeaklyCompressibleSolver<double, 2> solver(c, kind_of<Policy>());
  for (int step = 0; step < 200; ++step) {
    reference.advance(1e9);
    solver.advance(1e9);
  }
  const auto x = by_id<Vec<double, 2>>(solver.fluid_body(), "Position");
  const auto x_ref = by_id<Vec<double, 2>>(reference.fluid_body(), "Position");
  const auto v = by_id<Vec<double, 2>>(solver.fluid_body(), "Velocity");
  const auto v_ref = by_id<Vec<double, 2>>(reference.fluid_body(), "Velocity");
  double position = 0, velocity = 0, speed = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    position = std::max(position, norm(x[i] - x_ref[i]));
    velocity = std::max(velocity, norm(v[i] - v_ref[i]));
    speed = std::max(speed, norm(v_ref[i]));
  }
  std::printf("%s piston flume%s, 200 advection steps (t = %.3f, %d water particles): position %.2e, velocity %.2e "
              "relative to seq (bound 1e-9)\n",
              std::string(Policy::test_label).c_str(),
              (shifting > 0 ? " (kernel gradient corrected, particles shifted)"
               : corrected  ? " (kernel gradient corrected, h = " + std::to_string(smoothing_length_ratio).substr(0, 3) + " dx)"
                            : std::string())
                  .c_str(),
              solver.time(),
              int(x.size()), position, velocity / speed);
  EXPECT_EQ(solver.advection_steps(), reference.advection_steps());
  EXPECT_LE(position, 1e-9);
  EXPECT_LE(velocity / speed, 1e-9);
  // The velocity probe against its brute-force Shepard average over every water particle.
  const std::vector<double> probe = solver.observe().probe_velocity;
  ASSERT_EQ(probe.size(), 2u);
  const auto m = by_id<double, double, 2>(solver.fluid_body(), "Mass");
  const auto rho = by_id<double, double, 2>(solver.fluid_body(), "Density");
  const WendlandC2Kernel<double, 2> kernel = WendlandC2Kernel<double, 2>::from_spacing(c.dx, smoothing_length_ratio);
  Vec<double, 2> sum{};
  double weight = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double w = kernel.value(norm(Vec<double, 2>{{1.0, 0.5}} - x[i])) * m[i] / rho[i];
    sum += v[i] * w;
    weight += w;
  }
  const Vec<double, 2> expected = sum * (1 / weight);
  std::printf("%s piston flume: velocity probe at (1, 0.5) (%.6f, %.6f), brute force (%.6f, %.6f) (bound 1e-9 of the "
              "largest speed)\n",
              std::string(Policy::test_label).c_str(), probe[0], probe[1], expected[0], expected[1]);
  EXPECT_GT(norm(expected), 1e-3 * speed) << "the probe should see the wave's motion";
  EXPECT_LE(std::abs(probe[0] - expected[0]), 1e-9 * speed);
  EXPECT_LE(std::abs(probe[1] - expected[1]), 1e-9 * speed);
}

TYPED_TEST(WaveFlume, PolicesAgreeOnAShortPistonFlume) { expect_policies_agree_on_a_short_piston_flume<TypeParam>(false); }

TYPED_TEST(WaveFlume, PolicesAgreeWithTheKernelGradientCorrection) {
  expect_policies_agree_on_a_short_piston_flume<TypeParam>(true);
}

TYPED_TEST(WaveFlume, PolicesAgreeWithParticleShifting) {
  expect_policies_agree_on_a_short_piston_flume<TypeParam>(true, 0.4);
}

// The case files' flumes: the correction and h = 1.6 dx (geometry.smoothing_length_ratio).
TYPED_TEST(WaveFlume, PolicesAgreeWithTheCaseFilesKernel) {
  expect_policies_agree_on_a_short_piston_flume<TypeParam>(true, 0.0, 1.6);
}

TYPED_TEST(WaveFlume, DISABLED_PistonWaveHeightAtKd1) {
  const double depth = 1.0, g = 1.0, kd = 1.0, dx = 0.01;
  const double k = kd / depth, wavelength = 2 * std::numbers::pi / k;
  const double omega = std::sqrt(g * k * std::tanh(kd)), period = 2 * std::numbers::pi / omega;
  const double height = 0.1, stroke = height / piston_height_to_stroke(kd);
  const double group = omega / k / 2 * (1 + 2 * kd / std::sinh(2 * kd));
  // Gauges at 1, 1.5, 2 and 2.5 wavelengths from the paddle; the check is the last one's (the
  // issue's 2-3 wavelengths), the others show how the height changes along the flume.
  const std::vector<double> gauge_x = {1.0 * wavelength, 1.5 * wavelength, 2.0 * wavelength, 2.5 * wavelength};
  // Each gauge's window: from when the ramp's tail (two periods after the front) has passed it, five periods.
  const auto from_of = [&](double x) { return x / group + 2 * period; };
  const double to = from_of(gauge_x.back()) + 5 * period;
  // The far wall: nothing reflected there is back at the last gauge before its window ends.
  const double length = std::ceil(gauge_x.back() + (to - gauge_x.back() / group) * group / 2 + 1.0);
  const auto start = std::chrono::steady_clock::now();
  CaseDescription c = parse_case(flume_case(dx, length, stroke, period, gauge_x, to, 10.0), "piston_flume_2d.toml");
  // As the case files' flumes: without the correction the waves run too fast and the height at
  // 2.5 L fell 21 to 37 % short (docs/validation.md).
  c.kernel_gradient_correction = true;
  // And h = 1.6 dx, as the case files: with 1.3 dx the height at 2.5 L fell 15.8 % short on the
  // H100, with 1.6 dx 3.5 % (docs/validation.md, session 21).
  c.smoothing_length_ratio = 1.6;
  WeaklyCompressibleSolver<double, 2> solver(c, kind_of<TypeParam>());
  std::vector<std::vector<double>> t(gauge_x.size()), eta(gauge_x.size());
  for (int n = 0; n * 0.05 <= to + 1e-9; ++n) {
    const double until = 0.05 * n;
    while (solver.time() < until * (1 - 1e-12)) solver.advance(until);
    if (until < from_of(gauge_x.front())) continue;
    const std::vector<double> reading = solver.observe().gauge_elevation;
    for (std::size_t g = 0; g < gauge_x.size(); ++g)
      if (until >= from_of(gauge_x[g]) && until <= from_of(gauge_x[g]) + 5 * period + 1e-9)
        t[g].push_back(solver.time()), eta[g].push_back(reading.at(g));
  }
  int behind = 0;
  for (const Vec<double, 2>& x : solver.fluid_body().positions().to_vector()) behind += x[0] < -0.1 ? 1 : 0;
  for (std::size_t g = 0; g + 1 < gauge_x.size(); ++g)
    std::printf("%s gauge at %.1f L: wave height %.5f (%+.2f %% of Biesel's)\n", std::string(TypeParam::test_label).c_str(),
                gauge_x[g] / wavelength, 2 * fit_sinusoid(t[g], eta[g], period).amplitude,
                100 * (2 * fit_sinusoid(t[g], eta[g], period).amplitude / height - 1));
  const std::vector<double>& tt = t.back();
  const std::vector<double>& ee = eta.back();
  const double from = tt.front();
  const SinusoidFit fit = fit_sinusoid(tt, ee, period);
  // The best-fitting period: the least residual over 0.8 .. 1.2 of the paddle's.
  double best_period = period, best = fit.rms_residual;
  for (double f = 0.8; f <= 1.2; f += 1e-4)
    if (const SinusoidFit other = fit_sinusoid(tt, ee, f * period); other.rms_residual < best)
      best = other.rms_residual, best_period = f * period;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s piston flume k d = %.1f (L = %.3f d, T = %.4f, flume %.0f d, dx = d/%.0f, %d water particles, %d "
              "behind the paddle at the end): gauge at "
              "%.2f L, t = %.1f .. %.1f: wave height %.5f against Biesel's %.5f (%+.2f %%, bound 10 %%), period %.4f "
              "against %.4f (%+.2f %%, bound 1 %%), rms residual %.2e; stroke %.5f; %llu acoustic steps, %.0f s\n",
              std::string(TypeParam::test_label).c_str(), kd, wavelength, period, length, 1 / dx, int(solver.fluid_count()),
              behind, gauge_x.back() / wavelength, from, to, 2 * fit.amplitude, height, 100 * (2 * fit.amplitude / height - 1),
              best_period, period, 100 * (best_period / period - 1), fit.rms_residual, stroke,
              (unsigned long long)solver.acoustic_steps(), seconds);
  EXPECT_NEAR(2 * fit.amplitude / height, 1.0, 0.10);
  EXPECT_NEAR(best_period / period, 1.0, 0.01);
}
