// Time laws evaluated in kernels on every policy: the constant rate, the ramped sinusoid and
// the CSV table, each against its analytic form and against finite differences of itself; the
// ramp's continuity; the table's interpolation and its bad input (exact messages).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/motion/motion_table.hpp"
#include "unisph/motion/time_law.hpp"

namespace {
using namespace unisph;
namespace fs = std::filesystem;

constexpr Real eps = std::numeric_limits<Real>::epsilon();
const Real pi = std::numbers::pi_v<Real>;

struct LawKernel {
  TimeLaw law;
  View<const Real> times;
  View<LawState> out;
  UNISPH_HOST_DEVICE void operator()(Index i) const { out[i] = law(times[i]); }
};

struct RampKernel {
  View<const Real> rho;
  View<RampState> out;
  UNISPH_HOST_DEVICE void operator()(Index i) const { out[i] = smoothstep_ramp(rho[i]); }
};

// The law at each time, evaluated in a kernel on the policy.
template <class P>
std::vector<LawState> evaluate(P policy, const TimeLaw& law, const std::vector<Real>& times) {
  DiscreteVariable<Real> t("Times");
  t.assign(times);
  DiscreteVariable<LawState> out("LawStates", times.size());
  particle_for(policy, times.size(), LawKernel{law, t.read(policy), out.write(policy)});
  return out.to_vector();
}

// Central differences of the law's value and rate against its rate and acceleration at `times`
// (step h), within `tolerance` x the scale of each.
template <class P>
void expect_consistent_derivatives(P policy, const TimeLaw& law, const std::vector<Real>& times, Real h,
                                   Real rate_scale, Real acceleration_scale, Real tolerance) {
  std::vector<Real> shifted;
  for (Real t : times) {
    shifted.push_back(t - h);
    shifted.push_back(t + h);
  }
  const std::vector<LawState> at = evaluate(policy, law, times);
  const std::vector<LawState> around = evaluate(policy, law, shifted);
  for (std::size_t i = 0; i < times.size(); ++i) {
    const LawState& minus = around[2 * i];
    const LawState& plus = around[2 * i + 1];
    EXPECT_NEAR((plus.value - minus.value) / (2 * h), at[i].rate, tolerance * rate_scale) << "t = " << times[i];
    EXPECT_NEAR((plus.rate - minus.rate) / (2 * h), at[i].acceleration, tolerance * acceleration_scale)
        << "t = " << times[i];
  }
}

// A file in a fresh temporary folder, removed with it.
class TempFolder {
 public:
  TempFolder() : path_(fs::temp_directory_path() / ("unisph_time_law_test_" + std::to_string(::getpid()))) {
    fs::create_directories(path_);
  }
  ~TempFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path file = path_ / name;
    std::ofstream(file, std::ios::binary) << text;
    return file.string();
  }

 private:
  fs::path path_;
};

// The message of the Error `f` throws ("" if none).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

UNISPH_POLICY_TEST_SUITE(TimeLawTest);

TYPED_TEST(TimeLawTest, ConstantRateIsExact) {
  const TimeLaw law = constant_rate_law(Real(0.25));
  const std::vector<Real> times = {Real(-1), Real(0), Real(0.5), Real(3), Real(1e3)};
  const std::vector<LawState> got = evaluate(this->policy, law, times);
  for (std::size_t i = 0; i < times.size(); ++i) {
    EXPECT_EQ(got[i].value, Real(0.25) * times[i]);
    EXPECT_EQ(got[i].rate, Real(0.25));
    EXPECT_EQ(got[i].acceleration, Real(0));
  }
  expect_consistent_derivatives(this->policy, law, {Real(0.5), Real(3)}, Real(0.125), Real(0.25), Real(1), 4 * eps);
}

TYPED_TEST(TimeLawTest, RampValuesAreExactWhereArithmeticIsExact) {
  DiscreteVariable<Real> rho("Rho", {Real(-1), Real(0), Real(0.25), Real(0.5), Real(0.75), Real(1), Real(2)});
  DiscreteVariable<RampState> out("Ramp", rho.size());
  particle_for(this->policy, rho.size(), RampKernel{rho.read(this->policy), out.write(this->policy)});
  const std::vector<RampState> r = out.to_vector();
  // r = 10ρ³ - 15ρ⁴ + 6ρ⁵, r' = 30ρ²(1-ρ)², r'' = 60ρ(1-ρ)(1-2ρ), all exact in binary here.
  const RampState expected[] = {{0, 0, 0},
                                {0, 0, 0},
                                {Real(0.103515625), Real(1.0546875), Real(5.625)},
                                {Real(0.5), Real(1.875), Real(0)},
                                {Real(0.896484375), Real(1.0546875), Real(-5.625)},
                                {1, 0, 0},
                                {1, 0, 0}};
  for (std::size_t i = 0; i < r.size(); ++i) {
    EXPECT_EQ(r[i].value, expected[i].value) << i;
    EXPECT_EQ(r[i].first, expected[i].first) << i;
    EXPECT_EQ(r[i].second, expected[i].second) << i;
  }
}

TYPED_TEST(TimeLawTest, SinusoidWithoutRampIsTheSinusoid) {
  const Real amplitude = Real(0.05), period = Real(1.3), phase = Real(0.4);
  const TimeLaw law = sinusoid_law(amplitude, period, phase);
  const Real omega = 2 * pi / period;
  std::vector<Real> times;
  for (int i = 1; i <= 40; ++i) times.push_back(Real(0.11) * Real(i));
  const std::vector<LawState> got = evaluate(this->policy, law, times);
  for (std::size_t i = 0; i < times.size(); ++i) {
    const Real u = omega * times[i] + phase;
    EXPECT_NEAR(got[i].value, amplitude * std::sin(u), 16 * eps * amplitude);
    EXPECT_NEAR(got[i].rate, amplitude * omega * std::cos(u), 16 * eps * amplitude * omega);
    EXPECT_NEAR(got[i].acceleration, -amplitude * omega * omega * std::sin(u), 16 * eps * amplitude * omega * omega);
  }
  // At rest up to the start.
  for (const LawState& s : evaluate(this->policy, law, {Real(-2), Real(0)})) {
    EXPECT_EQ(s.value, Real(0));
    EXPECT_EQ(s.rate, Real(0));
    EXPECT_EQ(s.acceleration, Real(0));
  }
}

TYPED_TEST(TimeLawTest, RampedSinusoidAgainstItsAnalyticFormAndItsFiniteDifferences) {
  const Real amplitude = Real(0.08), period = Real(1.2), phase = Real(0.7), ramp_periods = Real(2.5), start = Real(0.3);
  const TimeLaw law = sinusoid_law(amplitude, period, phase, ramp_periods, start);
  const Real omega = 2 * pi / period, ramp = ramp_periods * period;
  std::vector<Real> times;
  // Through and past the ramp, off its ends (there the jerk jumps and a central difference of
  // the rate is only first-order; the continuity test looks at them).
  for (int i = 0; i < 80; ++i) times.push_back(start + (Real(0.0625) * Real(i) + Real(0.013)) * period);
  const std::vector<LawState> got = evaluate(this->policy, law, times);
  for (std::size_t i = 0; i < times.size(); ++i) {
    // The product rule written out here, with the ramp as its polynomial in ρ.
    const double tau = double(times[i]) - double(start);
    const double rho = std::min(tau / double(ramp), 1.0);
    const double r = 6 * std::pow(rho, 5) - 15 * std::pow(rho, 4) + 10 * std::pow(rho, 3);
    const double dr = (30 * std::pow(rho, 4) - 60 * std::pow(rho, 3) + 30 * rho * rho) / double(ramp);
    const double ddr = (120 * std::pow(rho, 3) - 180 * rho * rho + 60 * rho) / (double(ramp) * double(ramp));
    const double u = double(omega) * tau + double(phase), a = double(amplitude), w = double(omega);
    const double value = r * a * std::sin(u);
    const double rate = dr * a * std::sin(u) + r * a * w * std::cos(u);
    const double acceleration = ddr * a * std::sin(u) + 2 * dr * a * w * std::cos(u) - r * a * w * w * std::sin(u);
    EXPECT_NEAR(got[i].value, value, 64 * eps * a) << "t = " << times[i];
    EXPECT_NEAR(got[i].rate, rate, 64 * eps * a * w) << "t = " << times[i];
    EXPECT_NEAR(got[i].acceleration, acceleration, 64 * eps * a * w * w) << "t = " << times[i];
  }
  const Real h = std::cbrt(eps) * period;
  expect_consistent_derivatives(this->policy, law, times, h, amplitude * omega, amplitude * omega * omega,
                                400 * std::cbrt(eps * eps));
}

TYPED_TEST(TimeLawTest, RampKeepsDisplacementVelocityAndAccelerationContinuous) {
  // Just before and after the start and the ramp's end: every difference is O(δ).
  const Real amplitude = Real(0.1), period = Real(2), phase = Real(1.1), ramp_periods = Real(1.5), start = Real(1);
  const TimeLaw law = sinusoid_law(amplitude, period, phase, ramp_periods, start);
  const Real omega = 2 * pi / period;
  const Real delta = std::sqrt(eps) * period;
  for (Real joint : {start, start + ramp_periods * period}) {
    const std::vector<LawState> s = evaluate(this->policy, law, {joint - delta, joint + delta});
    // 2δ times the next derivative, which the ramp's terms keep within a few times A ω^(j+1).
    EXPECT_NEAR(s[0].value, s[1].value, 20 * delta * amplitude * omega) << "at " << joint;
    EXPECT_NEAR(s[0].rate, s[1].rate, 20 * delta * amplitude * omega * omega) << "at " << joint;
    EXPECT_NEAR(s[0].acceleration, s[1].acceleration, 20 * delta * amplitude * omega * omega * omega) << "at " << joint;
  }
  // Without a ramp the velocity jumps at the start (A ω cos φ): what the ramp is for.
  const TimeLaw abrupt = sinusoid_law(amplitude, period, phase);
  const std::vector<LawState> s = evaluate(this->policy, abrupt, {-delta, delta});
  EXPECT_EQ(s[0].rate, Real(0));
  EXPECT_NEAR(s[1].rate, amplitude * omega * std::cos(phase), 100 * delta * amplitude * omega * omega);
}

TYPED_TEST(TimeLawTest, TableThroughThreeRowsIsExact) {
  TempFolder folder;
  MotionTable table(folder.write("three.csv", "time,displacement\n0,0\n1,1\n2,0\n"));
  EXPECT_EQ(table.size(), Index(3));
  EXPECT_EQ(table.start_time(), Real(0));
  EXPECT_EQ(table.end_time(), Real(2));
  // The natural spline: m_0 = m_2 = 0, 4 m_1 = 6 (-1 - 1), m_1 = -3.
  const std::vector<LawState> got =
      evaluate(this->policy, table.law(this->policy), {Real(0.5), Real(1), Real(1.5), Real(-1), Real(0), Real(2), Real(3)});
  const LawState expected[] = {{Real(0.6875), Real(1.125), Real(-1.5)},  // 0.5 + 1.125/6, 1 + 0.75/6, -3/2
                               {Real(1), Real(0), Real(-3)},
                               {Real(0.6875), Real(-1.125), Real(-1.5)},
                               {Real(0), Real(0), Real(0)},  // before the first row: its value, at rest
                               {Real(0), Real(0), Real(0)},
                               {Real(0), Real(0), Real(0)},  // after the last: its value, at rest
                               {Real(0), Real(0), Real(0)}};
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].value, expected[i].value) << i;
    EXPECT_EQ(got[i].rate, expected[i].rate) << i;
    EXPECT_EQ(got[i].acceleration, expected[i].acceleration) << i;
  }
}

TYPED_TEST(TimeLawTest, TableOfAStraightLineIsTheLine) {
  TempFolder folder;
  // Uneven spacing, blanks, CRLF, a comment and no header.
  MotionTable table(folder.write("line.csv", "# a paddle at 2 m/s\r\n0, 0\r\n0.5 ,1\r\n\r\n1.5,3\r\n2,  4\r\n"));
  const std::vector<Real> times = {Real(0.25), Real(0.5), Real(0.75), Real(1.25), Real(1.75)};
  const std::vector<LawState> got = evaluate(this->policy, table.law(this->policy), times);
  for (std::size_t i = 0; i < times.size(); ++i) {
    EXPECT_EQ(got[i].value, 2 * times[i]) << times[i];
    EXPECT_EQ(got[i].rate, Real(2)) << times[i];
    EXPECT_EQ(got[i].acceleration, Real(0)) << times[i];
  }
}

TYPED_TEST(TimeLawTest, TableOfASampledSinusoid) {
  // A paddle signal: A sin ωt sampled 64 times a period over 3 periods (zero acceleration at
  // both ends, as the natural spline assumes).
  const double amplitude = 0.04, period = 1.6, omega = 2 * std::numbers::pi / period;
  const int per_period = 64, rows = 3 * per_period + 1;
  std::string text = "time,displacement\n";
  MotionTableRows in;
  in.source = "sampled sinusoid";
  for (int i = 0; i < rows; ++i) {
    const double t = period * i / per_period;
    char line[64];
    std::snprintf(line, sizeof line, "%.17g,%.17g\n", t, amplitude * std::sin(omega * t));
    text += line;
  }
  TempFolder folder;
  MotionTable table(folder.write("sine.csv", text));
  TimeLaw law = table.law(this->policy);
  const Real dt = Real(period / per_period);
  // Interpolation error: O(Δt⁴) in value, O(Δt³) in rate, O(Δt²) in acceleration.
  std::vector<Real> times;
  for (int i = 0; i < 3 * per_period; ++i) times.push_back(dt * (Real(i) + Real(0.37)));
  const std::vector<LawState> got = evaluate(this->policy, law, times);
  const double wdt = omega * period / per_period;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double t = double(times[i]);
    EXPECT_NEAR(got[i].value, amplitude * std::sin(omega * t), amplitude * (std::pow(wdt, 4) / 100 + 64 * eps));
    EXPECT_NEAR(got[i].rate, amplitude * omega * std::cos(omega * t), amplitude * omega * (std::pow(wdt, 3) / 50 + 64 * eps));
    EXPECT_NEAR(got[i].acceleration, -amplitude * omega * omega * std::sin(omega * t),
                amplitude * omega * omega * (std::pow(wdt, 2) / 10 + 256 * eps));
  }
  // The knots are met, and value, rate and acceleration are continuous across them.
  const Real delta = std::sqrt(eps) * dt;
  std::vector<Real> knots, around;
  for (int i = 1; i < rows - 1; i += 7) {
    knots.push_back(Real(period * i / per_period));
    around.push_back(knots.back() - delta);
    around.push_back(knots.back() + delta);
  }
  const std::vector<LawState> at = evaluate(this->policy, law, knots);
  const std::vector<LawState> near = evaluate(this->policy, law, around);
  for (std::size_t i = 0; i < knots.size(); ++i) {
    EXPECT_NEAR(at[i].value, Real(amplitude * std::sin(omega * double(knots[i]))), 8 * eps * amplitude);
    const LawState& l = near[2 * i];
    const LawState& r = near[2 * i + 1];
    EXPECT_NEAR(l.value, r.value, 4 * delta * amplitude * omega) << knots[i];
    EXPECT_NEAR(l.rate, r.rate, 4 * delta * amplitude * omega * omega) << knots[i];
    EXPECT_NEAR(l.acceleration, r.acceleration, 4 * delta * amplitude * omega * omega * omega + 256 * eps * amplitude * omega * omega)
        << knots[i];
  }
  // Rate and acceleration are the derivatives of the interpolated value.
  std::vector<Real> inside;
  for (int i = 0; i < 3 * per_period; i += 5) inside.push_back(dt * (Real(i) + Real(0.5)));
  expect_consistent_derivatives(this->policy, law, inside, std::cbrt(eps) * dt, Real(amplitude * omega),
                                Real(amplitude * omega * omega), 400 * std::cbrt(eps * eps));
}

TEST(HostTimeLaw, BadTablesAreOneLineErrors) {
  TempFolder folder;
  struct Case {
    const char* name;
    const char* text;
    const char* message;  // after "<path>"
  };
  const Case cases[] = {
      {"repeated_time.csv", "time,displacement\n0,0\n0.5,1\n0.5,2\n",
       ":4: time 0.5 is not after 0.5 on line 3 (times must increase strictly)"},
      {"decreasing_time.csv", "0,0\n1,1\n0.5,0\n", ":3: time 0.5 is not after 1 on line 2 (times must increase strictly)"},
      {"one_row.csv", "# comment\ntime,x\n0,0\n", ":3: the only row; a motion table needs at least 2 rows of time, displacement"},
      {"no_rows.csv", "time,displacement\n", ": no rows; a motion table needs at least 2 rows of time, displacement"},
      {"empty.csv", "", ": no rows; a motion table needs at least 2 rows of time, displacement"},
      {"text_value.csv", "0,0\n0.1,abc\n", ":2: expected a number (displacement), found 'abc'"},
      {"text_time.csv", "0,0\nx1,0\n", ":2: expected a number (time), found 'x1'"},
      {"three_fields.csv", "0,0,0\n1,1\n", ":1: expected 2 fields (time, displacement) separated by a comma, found 3: '0,0,0'"},
      {"one_field.csv", "time,displacement\n0 0\n1 1\n",
       ":2: expected 2 fields (time, displacement) separated by a comma, found 1: '0 0'"},
      {"empty_field.csv", "0,\n1,1\n", ":1: expected a number (displacement), found ''"},
      {"nan.csv", "0,0\n1,nan\n", ":2: the displacement 'nan' is not finite"},
      {"inf_time.csv", "0,0\ninf,1\n", ":2: the time 'inf' is not finite"},
  };
  for (const Case& c : cases) {
    const std::string path = folder.write(c.name, c.text);
    EXPECT_EQ(error_of([&] { MotionTable table(path); }), path + c.message) << c.name;
  }
  const std::string missing = (fs::temp_directory_path() / "unisph_no_such_table.csv").string();
  EXPECT_EQ(error_of([&] { MotionTable table(missing); }), missing + ": cannot open the file");
  // Rows made in code are named by their index.
  MotionTableRows rows{"paddle rows", {0.0, 1.0, 1.0}, {0.0, 0.1, 0.2}, {}};
  EXPECT_EQ(error_of([&] { MotionTable table(rows); }), "paddle rows: row 3: time 1 is not after 1 on row 2 (times must increase strictly)");
  rows = {"paddle rows", {0.0}, {0.0}, {}};
  EXPECT_EQ(error_of([&] { MotionTable table(rows); }),
            "paddle rows: row 1: the only row; a motion table needs at least 2 rows of time, displacement");
  rows = {"paddle rows", {0.0, 1.0}, {0.0}, {}};
  EXPECT_EQ(error_of([&] { MotionTable table(rows); }), "paddle rows: 2 times but 1 values");
}

TEST(HostTimeLaw, BadLawArgumentsAreOneLineErrors) {
  EXPECT_EQ(error_of([] { sinusoid_law(1, 0); }), "sinusoid law: the period must be positive and finite (it is 0)");
  EXPECT_EQ(error_of([] { sinusoid_law(1, -2.5, 0, 0, 0, "paddle.motion"); }),
            "paddle.motion: the period must be positive and finite (it is -2.5)");
  EXPECT_EQ(error_of([] { sinusoid_law(1, 1, 0, -1); }),
            "sinusoid law: the ramp must be a finite number of periods >= 0 (it is -1)");
  EXPECT_EQ(error_of([] { sinusoid_law(std::numeric_limits<Real>::quiet_NaN(), 1); }),
            "sinusoid law: the amplitude must be finite");
  EXPECT_EQ(error_of([] { constant_rate_law(std::numeric_limits<Real>::infinity()); }),
            "constant-rate law: the rate must be finite");
}

}  // namespace

// value_range holds every value a law takes at t >= 0 and reaches its ends: a ramped sinusoid
// (its amplitude), a table whose spline overshoots its knots (the turning points between them),
// a constant rate (unbounded unless zero).
TEST(HostTimeLaw, ValueRangeHoldsEveryValueAndReachesItsEnds) {
  const auto check = [](const TimeLaw& law, Real until, const char* what) {
    const LawRange r = value_range(law);
    ASSERT_TRUE(r.bounded) << what;
    Real lowest = std::numeric_limits<Real>::max(), highest = -lowest;
    const int samples = 200000;
    for (int i = 0; i <= samples; ++i) {
      const Real q = law(until * Real(i) / samples).value;
      EXPECT_GE(q, r.lowest - 64 * eps) << what << " at sample " << i;
      EXPECT_LE(q, r.highest + 64 * eps) << what << " at sample " << i;
      lowest = std::min(lowest, q), highest = std::max(highest, q);
    }
    // The samples come within the spacing's reach of the exact ends.
    EXPECT_NEAR(lowest, r.lowest, 1e-6) << what;
    EXPECT_NEAR(highest, r.highest, 1e-6) << what;
  };
  check(sinusoid_law(Real(0.05), Real(7.2), Real(0.3), Real(2), Real(1)), Real(60), "sinusoid");
  check(sinusoid_law(Real(-0.2), Real(1.5)), Real(10), "sinusoid of negative amplitude");
  // Knots 0, 1, 0, -0.5, -0.5 at uneven times: the natural spline bulges past 1 and below -0.5.
  MotionTable table(MotionTableRows{"rows", {0.5, 1.0, 2.5, 3.0, 4.0}, {0.0, 1.0, 0.0, -0.5, -0.5}, {}});
  const TimeLaw tabled = table.law(MemorySpace::host);
  const LawRange r = value_range(tabled);
  EXPECT_GT(r.highest, Real(1.0)) << "the spline overshoots its largest knot";
  EXPECT_LT(r.lowest, Real(-0.5)) << "and its smallest";
  check(tabled, Real(5), "table");
  EXPECT_FALSE(value_range(constant_rate_law(Real(0.1))).bounded);
  EXPECT_TRUE(value_range(constant_rate_law(Real(0))).bounded);
  EXPECT_EQ(value_range(no_motion()).highest, Real(0));
}
