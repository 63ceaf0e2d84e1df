// Free sloshing (issue 22; cases/sloshing_2d.toml), on every policy: a 2D rectangular tank of
// length L = 1 and depth d = 0.5 whose free surface starts as eta = d + a cos(pi x / L),
// a = 0.02 (a / d = 0.04), the water at rest with the pressure hydrostatic below that surface.
// The first mode's period, the best least-squares sinusoid through the free surface's elevation
// at a wave gauge beside the left wall over three periods (smoothed over 0.5 time units: a
// lattice start also rings acoustically), is within 2 % of linear theory,
// T1 = 2 pi / sqrt(g k tanh(k d)), k = pi / L (motion/sloshing.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/motion/sloshing.hpp"
#include "unisph/motion/wave_analysis.hpp"
#include "unisph/solver/case_file.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"

using namespace unisph;
using namespace unisph::sph;
using unisph::testing::kind_of;

UNISPH_POLICY_TEST_SUITE(Sloshing);

// The case file's method (`search`: its neighbour search; `corrected`: with
// fluid.kernel_gradient_correction; `shifting`: fluid.particle_shifting). Where
// `max_decrement` > 0, also the damping: the log-decrement per period from the amplitudes of
// the sinusoids of the found period fitted to the second and the last period of the record (the
// first holds the start's transient: the lattice cut by the cosine settles at the surface),
// bounded in size (neither a decay nor a growth).
template <class Policy>
void expect_first_mode_period_of_linear_theory(const char* search, bool corrected, double shifting = 0,
                                               double max_decrement = 0) {
  CaseDescription c = read_case_file(std::string(UNISPH_CASES_DIR) + "/sloshing_2d.toml");
  c.neighbor_search = search;
  c.kernel_gradient_correction = corrected;
  c.particle_shifting = shifting;
  const double length = 1.0, depth = 0.5, amplitude = 0.02, g = 1.0;
  // The pressure hydrostatic below the displaced surface (the water at rest).
  c.initial_fluid_state = [&](const std::vector<double>& x, std::vector<double>& velocity, double& pressure) {
    const double surface = depth + amplitude * std::cos(std::numbers::pi * x[0] / length);
    pressure = c.density * g * (surface - x[1]);
    velocity.assign(2, 0.0);
  };
  WeaklyCompressibleSolver<double, 2> solver(c, kind_of<Policy>());
  // The left gauge's elevation every 0.02 time units, then its mean over 0.5 time units (two
  // periods of the acoustic ringing of a lattice start, 4 d / c0 = 0.29).
  std::vector<double> t, eta;
  for (int k = 0; k * 0.02 <= c.end_time + 1e-9; ++k) {
    const double until = 0.02 * k;
    while (solver.time() < until * (1 - 1e-12)) solver.advance(until);
    const ObserverSample s = solver.observe();
    t.push_back(s.time);
    eta.push_back(s.gauge_elevation.at(0));
  }
  const int half = 12;  // 25 samples: 0.5 time units
  std::vector<double> ts, smooth;
  for (std::size_t k = half; k + half < eta.size(); ++k) {
    double sum = 0;
    for (std::size_t j = k - half; j <= k + half; ++j) sum += eta[j];
    ts.push_back(t[k]);
    smooth.push_back(sum / (2 * half + 1));
  }
  // The period: the one whose sinusoid (with a mean) fits the smoothed record best in least
  // squares, scanned from 0.5 to 1.5 of the theory's in steps of 1e-4 of it (with three periods
  // in the record, crossings of the mean are spoiled by the ringing's leftovers; the fit is not).
  const double theory = sloshing_natural_period(1, length, depth, g);
  const auto misfit = [&](double period) {
    const double omega = 2 * std::numbers::pi / period;
    // Normal equations of y = m + a cos + b sin.
    double n = 0, sc = 0, ss = 0, scc = 0, sss = 0, scs = 0, sy = 0, syc = 0, sys = 0, syy = 0;
    for (std::size_t k = 0; k < smooth.size(); ++k) {
      const double c = std::cos(omega * ts[k]), s = std::sin(omega * ts[k]), y = smooth[k];
      n += 1, sc += c, ss += s, scc += c * c, sss += s * s, scs += c * s, sy += y, syc += y * c, sys += y * s, syy += y * y;
    }
    const double m[3][3] = {{n, sc, ss}, {sc, scc, scs}, {ss, scs, sss}}, r[3] = {sy, syc, sys};
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    double x[3];
    for (int col = 0; col < 3; ++col) {
      double a[3][3];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) a[i][j] = j == col ? r[i] : m[i][j];
      x[col] = (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])) / det;
    }
    return syy - (x[0] * sy + x[1] * syc + x[2] * sys);  // the residual sum of squares
  };
  double period = theory, best = misfit(theory);
  for (double f = 0.5; f <= 1.5; f += 1e-4)
    if (const double e = misfit(f * theory); e < best) best = e, period = f * theory;
  if (std::getenv("UNISPH_SLOSHING_SERIES"))
    for (std::size_t k = 0; k < smooth.size(); k += 5) std::printf("%.3f %.5f\n", ts[k], smooth[k]);
  double low = 1e9, high = -1e9;
  for (double v : smooth) low = std::min(low, v), high = std::max(high, v);
  std::printf("%s sloshing L = 1, d = 0.5, a/d = 0.04, dx = d/50, %s search%s: first-mode period %.4f (least-squares "
              "sinusoid over t = %.2f .. %.2f at the left wall) against linear theory %.4f (%+.2f %%, bound 2 %%); smoothed "
              "elevation %.4f .. %.4f (d -+ a: %.2f .. %.2f)\n",
              std::string(Policy::test_label).c_str(), search, corrected ? ", kernel gradient corrected" : "", period,
              ts.front(), ts.back(), theory,
              100 * (period / theory - 1), low, high, depth - amplitude, depth + amplitude);
  EXPECT_NEAR(period / theory, 1.0, 0.02);
  if (max_decrement > 0) {
    const auto amplitude_over = [&](double from, double to) {
      std::vector<double> tw, yw;
      for (std::size_t k = 0; k < ts.size(); ++k)
        if (ts[k] >= from && ts[k] <= to) tw.push_back(ts[k]), yw.push_back(smooth[k]);
      return fit_sinusoid(tw, yw, period).amplitude;
    };
    const double second = amplitude_over(ts.front() + period, ts.front() + 2 * period);
    const double last = amplitude_over(ts.back() - period, ts.back());
    const double periods = ((ts.back() - 0.5 * period) - (ts.front() + 1.5 * period)) / period;
    const double decrement = std::log(second / last) / periods;
    std::printf("%s   amplitude %.5f over the second period, %.5f over the last, %.2f periods apart: log-decrement "
                "%+.4f per period (bound %.3f in size)\n",
                std::string(Policy::test_label).c_str(), second, last, periods, decrement, max_decrement);
    EXPECT_LT(std::abs(decrement), max_decrement);
  }
}

// The stored lists on every policy (the CPU's default): with "automatic" the GPU took its direct
// search, whose uncorrected standing wave runs 4.7 % fast (3.5283 on an H100, session 21); the
// direct search is checked with the correction below.
TYPED_TEST(Sloshing, FirstModePeriodMatchesLinearTheory) {
  expect_first_mode_period_of_linear_theory<TypeParam>("stored", false);
}

// The direct search at every policy (the GPU's default) with the kernel gradient corrected: without
// the correction the direct search's standing waves ran 4 % fast (docs/validation.md). Label
// `validation` (DISABLED_ in the quick entries): the direct search on the CPU takes 40 to 50 s here.
// The standing wave loses about 0.11 of its amplitude per period, measured from the second
// period to the last (0.114 on seq and par, session 20; the issue asks the period alone), and
// the bound of 0.15 keeps it from growing. The same with fluid.particle_shifting = 0.4 (the
// normal part removed over the band along the surface) keeps the period and loses as much
// (0.119 per period on par and on the H100, session 21: the shift does not carry the loss;
// docs/validation.md). Label `validation`.
TYPED_TEST(Sloshing, DISABLED_ParticleShiftingKeepsThePeriod) {
  expect_first_mode_period_of_linear_theory<TypeParam>("direct", true, 0.4, 0.15);
}

TYPED_TEST(Sloshing, DISABLED_FirstModePeriodWithTheDirectSearchAndTheKernelGradientCorrection) {
  expect_first_mode_period_of_linear_theory<TypeParam>("direct", true, 0.0, 0.15);
}

// Sloshing under sway (cases/sloshing_sway_2d.toml): the tank of the case above, the water at rest
// with a flat surface, the tank translated as X = A sin(omega t), A = 0.007, ramped over two
// periods, at omega = 0.8 and 1.2 times the first mode's frequency. The gauges 0.05 from the
// walls (x = -+0.45 from the centre) over the eight periods after the ramp and two more: the
// part of the sway's frequency, fitted together with a sinusoid of the first mode's frequency
// (the start excites that mode too, and with the kernel gradient corrected the run damps it by
// about 2 % a period), within 15 % of linear theory's E(x) (motion/sloshing.hpp), of its sign
// (phase within 30 degrees). Label `validation` (DISABLED_ in the quick entries): 40 to 60 s a
// frequency on this CPU.
template <class Policy>
void expect_sway_response_of_linear_theory(double frequency_ratio) {
  CaseDescription c = read_case_file(std::string(UNISPH_CASES_DIR) + "/sloshing_sway_2d.toml");
  const double length = 1.0, depth = 0.5, g = 1.0;
  const double natural = sloshing_natural_frequency(1, length, depth, g);
  const double omega = frequency_ratio * natural, period = 2 * std::numbers::pi / omega;
  ASSERT_EQ(c.bodies.front().name, "tank");
  MotionDescription& sway = c.bodies.front().translation;
  sway.period = period;
  const double amplitude = sway.amplitude;
  c.end_time = 12 * period;
  WeaklyCompressibleSolver<double, 2> solver(c, kind_of<Policy>());
  std::vector<double> t, left, right;
  for (int k = 0; k * 0.05 <= c.end_time + 1e-9; ++k) {
    const double until = 0.05 * k;
    while (solver.time() < until * (1 - 1e-12)) solver.advance(until);
    if (until < 4 * period) continue;
    const ObserverSample s = solver.observe();
    t.push_back(s.time);
    left.push_back(s.gauge_elevation.at(0) - depth);
    right.push_back(s.gauge_elevation.at(1) - depth);
  }
  const std::vector<double> periods = {period, 2 * std::numbers::pi / natural};
  const struct {
    const char* name;
    double x;  // from the tank's centre
    const std::vector<double>& eta;
  } gauges[] = {{"left", -0.45, left}, {"right", 0.45, right}};
  for (const auto& gauge : gauges) {
    const std::vector<SinusoidFit> fit = fit_sinusoids(t, gauge.eta, periods);
    const double theory = sway_elevation_amplitude(gauge.x, length, depth, amplitude, omega, g);
    // eta = E sin(omega t): the fitted sine coefficient carries E's sign, the cosine its phase error.
    const double phase_error = std::atan2(fit[0].cosine, fit[0].sine * (theory < 0 ? -1.0 : 1.0)) * 180 / std::numbers::pi;
    std::printf("%s swaying tank at %.1f omega_1 (A = %.3f, period %.4f), %s gauge over t = %.2f .. %.2f: the sway's part "
                "%.5f sin %+.5f cos, amplitude %.5f against linear theory's %+.5f (%.3f of it, bound 15 %%; phase %+.1f deg); "
                "the first mode's part %.5f; mean %+.5f; rms residual %.5f\n",
                std::string(Policy::test_label).c_str(), frequency_ratio, amplitude, period, gauge.name, t.front(), t.back(),
                fit[0].sine, fit[0].cosine, fit[0].amplitude, theory, fit[0].amplitude / std::abs(theory), phase_error,
                fit[1].amplitude, fit[0].mean, fit[0].rms_residual);
    EXPECT_NEAR(fit[0].amplitude / std::abs(theory), 1.0, 0.15) << gauge.name;
    EXPECT_LT(std::abs(phase_error), 30.0) << gauge.name;
  }
}

TYPED_TEST(Sloshing, DISABLED_SwayResponseBelowResonanceMatchesLinearTheory) {
  expect_sway_response_of_linear_theory<TypeParam>(0.8);
}

TYPED_TEST(Sloshing, DISABLED_SwayResponseAboveResonanceMatchesLinearTheory) {
  expect_sway_response_of_linear_theory<TypeParam>(1.2);
}
