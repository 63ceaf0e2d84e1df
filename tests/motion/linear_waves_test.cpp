// Linear wave theory in kernels on every policy (double whatever unisph::Real is): the
// dispersion relation against reference values and its deep and shallow limits, Biésel's
// transfer functions and their limits, the two-gauge separation; on the host, the sinusoid fit
// and the two-gauge analysis of synthetic series, and their bad input.
//
// Reference values: Python's mpmath at 40 digits (findroot of x tanh x = y; the transfer
// functions in their textbook forms), and the classic table of d/L against d/L0 (0.1 -> 0.1410).
#include <cmath>
#include <iterator>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/motion/linear_waves.hpp"
#include "unisph/motion/wave_analysis.hpp"

namespace {
using namespace unisph;

constexpr double eps = std::numeric_limits<double>::epsilon();
constexpr double pi = std::numbers::pi;
constexpr double g = 9.81;

struct DispersionKernel {
  View<const double> omega, depth;
  View<double> k;
  UNISPH_HOST_DEVICE void operator()(Index i) const { k[i] = wave_number(omega[i], depth[i], g); }
};

struct TransferKernel {
  View<const double> kd;
  View<double> piston, flap;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    piston[i] = piston_height_to_stroke(kd[i]);
    flap[i] = flap_height_to_stroke(kd[i]);
  }
};

struct SeparationKernel {
  View<const double> coefficients;  // a1, b1, a2, b2 per case
  double k, spacing;
  View<IncidentReflected<double>> out;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    const double* c = coefficients.data() + 4 * i;
    out[i] = separate_incident_reflected(c[0], c[1], c[2], c[3], k, spacing);
  }
};

template <class P>
std::vector<double> wave_numbers(P policy, const std::vector<double>& omega, const std::vector<double>& depth) {
  DiscreteVariable<double> w("Omega"), d("Depth"), k("K", omega.size());
  w.assign(omega);
  d.assign(depth);
  particle_for(policy, omega.size(), DispersionKernel{w.read(policy), d.read(policy), k.write(policy)});
  return k.to_vector();
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::string text(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

// a_I sin(ωt - k(x - x1) + φ_I) + a_R sin(ωt + k(x - x1) + φ_R) + mean, sampled at `times`.
std::vector<double> synthetic_gauge(const std::vector<double>& times, double omega, double k, double offset,
                                    double incident, double incident_phase, double reflected, double reflected_phase,
                                    double mean) {
  std::vector<double> eta;
  for (double t : times)
    eta.push_back(incident * std::sin(omega * t - k * offset + incident_phase) +
                  reflected * std::sin(omega * t + k * offset + reflected_phase) + mean);
  return eta;
}

UNISPH_POLICY_TEST_SUITE(LinearWavesTest);

TYPED_TEST(LinearWavesTest, DispersionAgainstReferenceValues) {
  // (period, depth) -> k from mpmath.
  struct Case {
    double period, depth, k;
  };
  const Case cases[] = {{10.0, 10.0, 0.06801907425474224471}, {2.0, 0.5, 1.548945987239953806}, {1.5, 0.6, 2.101122073529521610}};
  std::vector<double> omega, depth;
  for (const Case& c : cases) {
    omega.push_back(2 * pi / c.period);
    depth.push_back(c.depth);
  }
  // The table's entry d/L0 = 0.1 (L0 = g T² / 2π): d/L = 0.14098069687542476 (0.1410 in the table).
  omega.push_back(2 * pi / 3.0);
  depth.push_back(0.1 * g * 9.0 / (2 * pi));
  const std::vector<double> k = wave_numbers(this->policy, omega, depth);
  for (std::size_t i = 0; i < std::size(cases); ++i) EXPECT_NEAR(k[i], cases[i].k, 2 * eps * cases[i].k) << i;
  const double d_over_l = depth[3] * k[3] / (2 * pi);
  EXPECT_NEAR(d_over_l, 0.14098069687542476181, 4 * eps);
  EXPECT_NEAR(d_over_l, 0.1410, 0.00005);
  EXPECT_NEAR(std::tanh(k[3] * depth[3]), 0.7093, 0.00005);
}

TYPED_TEST(LinearWavesTest, DispersionToMachinePrecisionDeepAndShallow) {
  // y = ω² d / g from 1e-10 (very shallow) to 1e4 (deep): the residual of ω² = g k tanh(kd).
  std::vector<double> omega, depth;
  for (int e = -40; e <= 16; ++e) {
    const double y = std::pow(10.0, e / 4.0);
    omega.push_back(1.3);
    depth.push_back(y * g / (1.3 * 1.3));
  }
  const std::size_t sweep = omega.size();
  omega.push_back(2 * pi);  // deep water: 1000 m at T = 1 s, kd = 4024
  depth.push_back(1000.0);
  omega.push_back(2 * pi);  // infinite depth: exactly ω²/g
  depth.push_back(std::numeric_limits<double>::infinity());
  omega.push_back(1e-4);  // shallow: y = 1e-8 ...
  depth.push_back(1e-8 * g / 1e-8);
  omega.push_back(0.0);
  depth.push_back(1.0);
  omega.push_back(-1.0);
  depth.push_back(1.0);
  const std::vector<double> k = wave_numbers(this->policy, omega, depth);
  for (std::size_t i = 0; i < sweep; ++i) {
    const double back = g * k[i] * std::tanh(k[i] * depth[i]);
    EXPECT_NEAR(back, omega[i] * omega[i], 4 * eps * omega[i] * omega[i]) << "y = " << omega[i] * omega[i] * depth[i] / g;
  }
  const double k_deep = 4 * pi * pi / g;
  EXPECT_NEAR(k[sweep], k_deep, eps * k_deep);
  EXPECT_EQ(k[sweep + 1], k_deep);
  // ... where x tanh x = y gives x = √y (1 + y/6 + 11 y²/360 + ...): kd = 1e-4 (1 + 1.6667e-9).
  const double y = 1e-8, x = std::sqrt(y) * (1 + y / 6 + 11 * y * y / 360);
  EXPECT_NEAR(k[sweep + 2] * depth[sweep + 2], x, 2 * eps * x);
  EXPECT_NEAR(k[sweep + 2], 1e-4 / std::sqrt(g * depth[sweep + 2]), 2e-9 * k[sweep + 2]);  // ω / √(g d)
  EXPECT_EQ(k[sweep + 3], 0.0);
  EXPECT_TRUE(std::isnan(k[sweep + 4]));
}

TYPED_TEST(LinearWavesTest, BieselTransferFunctions) {
  const std::vector<double> kd = {1e-3, 0.5, 1.0, 2.0, 10.0, 1e-6, 1e-4, 40.0, 1000.0, 0.0};
  // mpmath: 2 (cosh 2x - 1)/(sinh 2x + 2x) and 4 (sinh x/x)(x sinh x - cosh x + 1)/(sinh 2x + 2x).
  const double piston_ref[] = {0.00099999999999997777778, 0.49933830158073696446, 0.98178930731303442302,
                               1.6815789361329113469, 1.9999998268631100066};
  const double flap_ref[] = {0.00050000004166665138889, 0.25474376376054893795, 0.52808762358926084572,
                             1.0412385908643425026, 1.8000180033227079706};
  DiscreteVariable<double> x("KD"), piston("Piston", kd.size()), flap("Flap", kd.size());
  x.assign(kd);
  particle_for(this->policy, kd.size(), TransferKernel{x.read(this->policy), piston.write(this->policy), flap.write(this->policy)});
  const std::vector<double> p = piston.to_vector(), f = flap.to_vector();
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(p[i], piston_ref[i], 8 * eps * piston_ref[i]) << "kd = " << kd[i];
    EXPECT_NEAR(f[i], flap_ref[i], 8 * eps * flap_ref[i]) << "kd = " << kd[i];
  }
  // Shallow water: piston H/S = kd (1 - (kd)⁴/45 + ...), flap H/S = kd/2 (1 + (kd)²/6 ...).
  for (int i : {5, 6}) {
    EXPECT_NEAR(p[i], kd[i], 4 * eps * kd[i]) << kd[i];
    EXPECT_NEAR(f[i], kd[i] / 2, (kd[i] * kd[i] / 6 + 4 * eps) * kd[i] / 2) << kd[i];
  }
  // Deep water: both → 2 (the flap as 2 (1 - 1/kd)); no overflow.
  EXPECT_NEAR(p[7], 2.0, 4 * eps);
  EXPECT_EQ(p[8], 2.0);
  EXPECT_NEAR(f[8], 2.0 * (1 - 1 / kd[8]), 1e-5);
  EXPECT_EQ(p[9], 0.0);
  EXPECT_EQ(f[9], 0.0);
}

TYPED_TEST(LinearWavesTest, TwoGaugeSeparationOfKnownWaves) {
  // Incident 0.05 at phase 0.3, reflected 0.012 at -1.1; gauges 0.4 m apart, k = 2.1 rad/m.
  const double k = 2.101122073529521610, spacing = 0.4, omega = 1.0;
  const double ai = 0.05, pi_ = 0.3, ar = 0.012, pr = -1.1;
  // Cosine and sine coefficients of each gauge: a sin(ωt + φ) = a sin φ cos ωt + a cos φ sin ωt.
  auto coefficients = [&](double offset, double& a, double& b) {
    a = ai * std::sin(-k * offset + pi_) + ar * std::sin(k * offset + pr);
    b = ai * std::cos(-k * offset + pi_) + ar * std::cos(k * offset + pr);
  };
  double a1, b1, a2, b2;
  coefficients(0.0, a1, b1);
  coefficients(spacing, a2, b2);
  DiscreteVariable<double> c("Coefficients", {a1, b1, a2, b2});
  DiscreteVariable<IncidentReflected<double>> out("Separated", 1);
  particle_for(this->policy, 1, SeparationKernel{c.read(this->policy), k, spacing, out.write(this->policy)});
  const IncidentReflected<double> s = out.to_vector()[0];
  EXPECT_NEAR(s.incident_amplitude, ai, 16 * eps * ai);
  EXPECT_NEAR(s.reflected_amplitude, ar, 16 * eps * ai);
  EXPECT_NEAR(s.incident_phase, pi_, 16 * eps);
  EXPECT_NEAR(s.reflected_phase, pr, 16 * eps * ai / ar);
  EXPECT_NEAR(s.reflection_coefficient, ar / ai, 32 * eps);
  (void)omega;
}

TEST(HostLinearWaves, StrokesAndFlapAngle) {
  // A piston wave of 4 cm and 1.5 s in 0.6 m: S = H / (H/S)(kd).
  const double k = wave_number_for_period(1.5, 0.6, g);
  EXPECT_NEAR(k, 2.101122073529521610, 2 * eps * k);
  EXPECT_NEAR(wave_length(1.5, 0.6, g), 2.99039517329182215942122, 4 * eps * 3);
  EXPECT_NEAR(dispersion_frequency(k, 0.6, g), 2 * pi / 1.5, 4 * eps * 4.2);
  const double s = piston_stroke(0.04, 1.5, 0.6, g);
  EXPECT_NEAR(s * piston_height_to_stroke(k * 0.6), 0.04, 4 * eps * 0.04);
  const double f = flap_stroke(0.04, 1.5, 0.6, g);
  EXPECT_NEAR(f * flap_height_to_stroke(k * 0.6), 0.04, 4 * eps * 0.04);
  EXPECT_GT(f, s);  // a flap moves less water below the surface than a piston
  EXPECT_EQ(flap_angle_amplitude(0.1, 0.05), std::atan(1.0));
  EXPECT_TRUE(std::isnan(wave_number(1.0, 0.0, g)));
  EXPECT_TRUE(std::isnan(piston_height_to_stroke(-1.0)));
}

TEST(HostWaveAnalysis, SinusoidFitRecoversAnExactSinusoid) {
  // Irregular samples over 3.7 periods: mean 0.02, 0.3 cos ωt - 0.1 sin ωt.
  const double period = 1.7, omega = 2 * pi / period;
  std::vector<double> t, y;
  for (int i = 0; i < 400; ++i) {
    const double time = 0.5 + 3.7 * period * (i + 0.3 * std::sin(1.0 * i)) / 400;
    t.push_back(time);
    y.push_back(0.02 + 0.3 * std::cos(omega * time) - 0.1 * std::sin(omega * time));
  }
  const SinusoidFit fit = fit_sinusoid(t, y, period);
  EXPECT_NEAR(fit.mean, 0.02, 1e-14);
  EXPECT_NEAR(fit.cosine, 0.3, 1e-14);
  EXPECT_NEAR(fit.sine, -0.1, 1e-14);
  EXPECT_NEAR(fit.amplitude, std::hypot(0.3, 0.1), 1e-14);
  EXPECT_NEAR(fit.phase, std::atan2(0.3, -0.1), 1e-13);
  EXPECT_LT(fit.rms_residual, 1e-15);
  // As a sine: amplitude sin(ωt + phase) is the series less its mean.
  for (std::size_t i = 0; i < t.size(); i += 37)
    EXPECT_NEAR(fit.amplitude * std::sin(omega * t[i] + fit.phase), y[i] - 0.02, 1e-14);
}

TEST(HostWaveAnalysis, TwoGaugesRecoverIncidentAndReflectedWaves) {
  // T = 1.5 s in 0.6 m (L = 2.99 m); gauges at 2.0 m and 2.45 m (Δ/L = 0.15), 12.3 s at 50 Hz
  // (not whole periods), a mean level of 3 mm.
  const double period = 1.5, depth = 0.6, spacing = 0.45, omega = 2 * pi / period;
  const double k = wave_number_for_period(period, depth, g);
  std::vector<double> t;
  for (int i = 0; i <= 615; ++i) t.push_back(0.02 * i);
  const double ai = 0.05, phase_i = 0.3, ar = 0.012, phase_r = -1.1;
  const std::vector<double> one = synthetic_gauge(t, omega, k, 0.0, ai, phase_i, ar, phase_r, 0.003);
  const std::vector<double> two = synthetic_gauge(t, omega, k, spacing, ai, phase_i, ar, phase_r, 0.003);
  const IncidentReflected<double> r = two_gauge_reflection(t, one, two, period, spacing, depth, g);
  EXPECT_NEAR(r.incident_amplitude, ai, 1e-13);
  EXPECT_NEAR(r.reflected_amplitude, ar, 1e-13);
  EXPECT_NEAR(r.incident_phase, phase_i, 1e-12);
  EXPECT_NEAR(r.reflected_phase, phase_r, 1e-11);
  EXPECT_NEAR(r.reflection_coefficient, 0.24, 1e-12);
  // A standing wave (full reflection) and no reflection at all.
  const std::vector<double> s1 = synthetic_gauge(t, omega, k, 0.0, ai, 0.0, ai, 0.0, 0.0);
  const std::vector<double> s2 = synthetic_gauge(t, omega, k, spacing, ai, 0.0, ai, 0.0, 0.0);
  EXPECT_NEAR(two_gauge_reflection(t, s1, s2, period, spacing, depth, g).reflection_coefficient, 1.0, 1e-12);
  const std::vector<double> p1 = synthetic_gauge(t, omega, k, 0.0, ai, 0.7, 0.0, 0.0, 0.0);
  const std::vector<double> p2 = synthetic_gauge(t, omega, k, spacing, ai, 0.7, 0.0, 0.0, 0.0);
  EXPECT_NEAR(two_gauge_reflection(t, p1, p2, period, spacing, depth, g).reflection_coefficient, 0.0, 1e-12);
}

TEST(HostWaveAnalysis, SinusoidsOfTwoPeriodsAreSeparated) {
  // A forced response and a free oscillation in one record (the swaying tank's gauges): mean
  // 0.004, 0.02 sin at the sway's period 3.08 and 0.015 cos + 0.005 sin at 3.70, over 8 periods.
  const double forced = 3.08, natural = 3.70;
  const double wf = 2 * pi / forced, wn = 2 * pi / natural;
  std::vector<double> t, y;
  for (int i = 0; i < 500; ++i) {
    const double time = 12.0 + 8 * forced * i / 500.0;
    t.push_back(time);
    y.push_back(0.004 + 0.02 * std::sin(wf * time) + 0.015 * std::cos(wn * time) + 0.005 * std::sin(wn * time));
  }
  const std::vector<double> periods = {forced, natural};
  const std::vector<SinusoidFit> fits = fit_sinusoids(t, y, periods);
  ASSERT_EQ(fits.size(), 2u);
  EXPECT_NEAR(fits[0].mean, 0.004, 1e-14);
  EXPECT_NEAR(fits[0].cosine, 0.0, 1e-14);
  EXPECT_NEAR(fits[0].sine, 0.02, 1e-14);
  EXPECT_NEAR(fits[1].cosine, 0.015, 1e-14);
  EXPECT_NEAR(fits[1].sine, 0.005, 1e-14);
  EXPECT_EQ(fits[1].mean, fits[0].mean);
  EXPECT_LT(fits[0].rms_residual, 1e-15);
  // One period alone is fit_sinusoid, bit for bit.
  const SinusoidFit one = fit_sinusoid(t, y, forced);
  const SinusoidFit same = fit_sinusoids(t, y, std::vector<double>{forced}).front();
  EXPECT_EQ(one.cosine, same.cosine);
  EXPECT_EQ(one.sine, same.sine);
  EXPECT_EQ(one.rms_residual, same.rms_residual);
  // The fit of the forced period alone is spoiled by the free oscillation: why both are fitted.
  EXPECT_GT(std::abs(one.sine - 0.02), 1e-3);
  // No period, and a window too short to tell two close periods apart.
  EXPECT_EQ(error_of([&] { fit_sinusoids(t, y, std::vector<double>{}); }), "fit_sinusoids: no period given");
  EXPECT_EQ(error_of([&] { fit_sinusoids(std::vector<double>{0, 1, 2, 3}, std::vector<double>{0, 1, 0, 1},
                                         std::vector<double>{1.0, 2.0}); }),
            "fit_sinusoids: 4 samples; a mean and 2 sinusoids need at least 5");
}

TEST(HostWaveAnalysis, BadSeriesAreOneLineErrors) {
  const std::vector<double> t = {0, 0.1, 0.2, 0.3}, y = {0, 1, 0, -1}, short_y = {0, 1, 0};
  EXPECT_EQ(error_of([&] { fit_sinusoid(t, short_y, 1.0); }), "fit_sinusoid: 4 times but 3 values");
  EXPECT_EQ(error_of([&] { fit_sinusoid(std::vector<double>{0, 1}, std::vector<double>{0, 1}, 1.0); }),
            "fit_sinusoid: 2 samples; a sinusoid with a mean needs at least 3");
  EXPECT_EQ(error_of([&] { fit_sinusoid(t, y, -2.0); }), "fit_sinusoid: the period must be positive and finite (it is -2)");
  EXPECT_EQ(error_of([&] { fit_sinusoid(t, std::vector<double>{0, 1, std::nan(""), 2}, 1.0); }),
            "fit_sinusoid: sample 2 is not finite");
  // Every sample at the same phase: t = 0, 1, 2, 3 with a period of 1.
  EXPECT_EQ(error_of([&] { fit_sinusoid(std::vector<double>{0, 1, 2, 3}, y, 1.0); }),
            "fit_sinusoid: the 4 samples over [0, 3] do not determine a sinusoid of period 1 (too short a window, or "
            "every sample at the same phase)");
  EXPECT_EQ(error_of([&] { two_gauge_reflection(t, y, short_y, 1.0, 0.3, 1.0, g); }),
            "two_gauge_reflection: 4 times but 4 and 3 gauge values");
  EXPECT_EQ(error_of([&] { two_gauge_reflection(t, y, y, 1.0, 0.0, 1.0, g); }),
            "two_gauge_reflection: the gauge spacing must be positive and finite (it is 0)");
  EXPECT_EQ(error_of([&] { two_gauge_reflection(t, y, y, 1.0, 0.3, -1.0, g); }),
            "two_gauge_reflection: the depth and gravity must be positive (they are -1 and 9.81)");
  // Half a wave length apart: sin kΔ = 0.
  const double length = wave_length(1.5, 0.6, g);
  EXPECT_EQ(error_of([&] { two_gauge_reflection(t, y, y, 1.5, 0.5 * length, 0.6, g); }),
            "two_gauge_reflection: the gauges are " + text(0.5) + " wave lengths apart (L = " + text(length) +
                "); Goda & Suzuki's method needs 0.05 to 0.45 of a wave length, modulo half a wave length");
}

}  // namespace
