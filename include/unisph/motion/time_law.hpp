#pragma once
// Time laws of prescribed motions: one scalar coordinate q(t) (a displacement along a direction,
// or an angle about an axis) with its first two time derivatives, exact, at any time.
//
//   constant rate    q = c t                                   (a tank moving at constant velocity)
//   sinusoid         q = r(τ / T_r) A sin(ω τ + φ),  τ = t - t_s  (piston or flap paddle, sway, roll)
//   table            q = the natural cubic spline through (t_i, q_i) read from a CSV file
//                    (motion_table.hpp)
//
// The values are trivially copyable and their evaluation is UNISPH_HOST_DEVICE, so a kernel on
// any policy evaluates them; the table's knots are a View in the policy's memory space. The
// factories (host) check their arguments and throw a one-line unisph::Error. docs/motion.md
// writes out every formula.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <string_view>

#include "unisph/core/config.hpp"
#include "unisph/core/error.hpp"
#include "unisph/memory/view.hpp"

namespace unisph {

// A coordinate and its first two time derivatives at one time.
struct LawState {
  Real value;         // q(t)
  Real rate;          // dq/dt
  Real acceleration;  // d²q/dt²
};

// The ramp of the sinusoid law, as a function of the fraction ρ of the ramp's duration:
//   r(ρ) = 0 for ρ <= 0,   10 ρ³ - 15 ρ⁴ + 6 ρ⁵ for 0 < ρ < 1,   1 for ρ >= 1
// (the quintic "smoothstep"). r' = 30 ρ² (1 - ρ)² and r'' = 60 ρ (1 - ρ)(1 - 2ρ) vanish at both
// ends, so r, r' and r'' are continuous everywhere: a ramped sinusoid starts from rest with
// continuous displacement, velocity and acceleration, and joins the full sinusoid the same way.
// (A half-cosine ramp, (1 - cos πρ)/2, keeps the velocity continuous but not the acceleration.)
struct RampState {
  Real value;   // r(ρ)
  Real first;   // dr/dρ
  Real second;  // d²r/dρ²
};

UNISPH_HOST_DEVICE inline RampState smoothstep_ramp(Real rho) {
  if (!(rho > Real(0))) return {Real(0), Real(0), Real(0)};
  if (rho >= Real(1)) return {Real(1), Real(0), Real(0)};
  const Real rest = Real(1) - rho;
  return {rho * rho * rho * (Real(10) + rho * (Real(-15) + Real(6) * rho)), Real(30) * rho * rho * rest * rest,
          Real(60) * rho * rest * (Real(1) - Real(2) * rho)};
}

// q = c t at every time.
struct ConstantRateLaw {
  Real rate;  // c
  UNISPH_HOST_DEVICE LawState operator()(Real t) const { return {rate * t, rate, Real(0)}; }
};

// q = r(τ / T_r) A sin(ω τ + φ) for τ = t - t_s > 0, and q = 0 (at rest) before t_s.
// With T_r = 0 there is no ramp (r = 1 from t_s on).
//   dq/dt   = r' A sin + r A ω cos
//   d²q/dt² = r'' A sin + 2 r' A ω cos - r A ω² sin
// where r' = (dr/dρ) / T_r and r'' = (d²r/dρ²) / T_r² are the ramp's time derivatives.
struct SinusoidLaw {
  Real amplitude;          // A
  Real angular_frequency;  // ω = 2π / T
  Real phase;              // φ (radians)
  Real ramp_duration;      // T_r = (ramp periods) x T; 0: no ramp
  Real start;              // t_s

  UNISPH_HOST_DEVICE LawState operator()(Real t) const {
    const Real tau = t - start;
    if (!(tau > Real(0))) return {Real(0), Real(0), Real(0)};
    const Real argument = angular_frequency * tau + phase;
    const Real s = std::sin(argument), c = std::cos(argument);
    const Real f = amplitude * s;                                            // the sinusoid
    const Real df = amplitude * angular_frequency * c;                       // its rate
    const Real ddf = -amplitude * angular_frequency * angular_frequency * s;  // its acceleration
    if (!(ramp_duration > Real(0))) return {f, df, ddf};
    const RampState r = smoothstep_ramp(tau / ramp_duration);
    const Real dr = r.first / ramp_duration, ddr = r.second / (ramp_duration * ramp_duration);
    return {r.value * f, dr * f + r.value * df, ddr * f + Real(2) * dr * df + r.value * ddf};
  }
};

// One knot of a table law: time, coordinate, and the spline's second derivative there.
struct TableKnot {
  Real time;
  Real value;
  Real second_derivative;
};

// The natural cubic spline through the knots (at least two, times strictly increasing; built
// by MotionTable, motion_table.hpp). On [t_i, t_i+1], h = t_i+1 - t_i, a = (t_i+1 - t)/h, b = 1 - a:
//   q   = a q_i + b q_i+1 + ((a³ - a) m_i + (b³ - b) m_i+1) h²/6
//   q'  = (q_i+1 - q_i)/h - (3a² - 1) h m_i / 6 + (3b² - 1) h m_i+1 / 6
//   q'' = a m_i + b m_i+1
// with m the second derivatives (m_0 = m_n = 0: "natural"). q, q' and q'' are continuous at
// every knot. Before the first knot the coordinate is the first row's and after the last the
// last row's, at rest (rate and acceleration 0).
struct TableLaw {
  View<const TableKnot> knots;

  UNISPH_HOST_DEVICE LawState operator()(Real t) const {
    const Index n = knots.size();
    if (n == 0) return {Real(0), Real(0), Real(0)};
    if (!(t > knots[0].time)) return {knots[0].value, Real(0), Real(0)};
    if (!(t < knots[n - 1].time)) return {knots[n - 1].value, Real(0), Real(0)};
    // The interval [t_lo, t_hi) holding t, by bisection.
    Index lo = 0, hi = n - 1;
    while (hi - lo > 1) {
      const Index mid = lo + (hi - lo) / 2;
      if (knots[mid].time <= t) lo = mid;
      else hi = mid;
    }
    const TableKnot k0 = knots[lo], k1 = knots[hi];
    const Real h = k1.time - k0.time;
    const Real a = (k1.time - t) / h, b = (t - k0.time) / h;
    const Real value = a * k0.value + b * k1.value +
                       ((a * a * a - a) * k0.second_derivative + (b * b * b - b) * k1.second_derivative) * (h * h) / Real(6);
    const Real rate = (k1.value - k0.value) / h + ((Real(3) * b * b - Real(1)) * k1.second_derivative -
                                                   (Real(3) * a * a - Real(1)) * k0.second_derivative) * h / Real(6);
    const Real acceleration = a * k0.second_derivative + b * k1.second_derivative;
    return {value, rate, acceleration};
  }
};

enum class TimeLawKind : int { none, constant_rate, sinusoid, table };

// Any of the laws above (kind none: q = 0 at all times), chosen at run time. Build it with the
// factories below or MotionTable::law(policy).
struct TimeLaw {
  TimeLawKind kind;
  ConstantRateLaw constant_rate;
  SinusoidLaw sinusoid;
  TableLaw table;

  UNISPH_HOST_DEVICE LawState operator()(Real t) const {
    switch (kind) {
      case TimeLawKind::constant_rate: return constant_rate(t);
      case TimeLawKind::sinusoid: return sinusoid(t);
      case TimeLawKind::table: return table(t);
      default: return {Real(0), Real(0), Real(0)};
    }
  }
};

namespace detail {
[[noreturn]] inline void time_law_error(std::string_view where, const std::string& what) {
  throw Error(std::string(where) + ": " + what);
}
// A number as it reads in a message: "2.5", "-1", "1e-09", "nan".
inline std::string law_number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}
}  // namespace detail

// q = 0 at all times.
inline TimeLaw no_motion() { return TimeLaw{TimeLawKind::none, {}, {}, {}}; }

// q = rate t. `where` names the law in the error message (a case file's key, for example).
inline TimeLaw constant_rate_law(Real rate, std::string_view where = "constant-rate law") {
  if (!std::isfinite(rate)) detail::time_law_error(where, "the rate must be finite");
  TimeLaw law = no_motion();
  law.kind = TimeLawKind::constant_rate;
  law.constant_rate = {rate};
  return law;
}

// q = r A sin(2π τ / period + phase), ramped over `ramp_periods` periods (0: no ramp) from `start` on.
inline TimeLaw sinusoid_law(Real amplitude, Real period, Real phase = Real(0), Real ramp_periods = Real(0),
                            Real start = Real(0), std::string_view where = "sinusoid law") {
  if (!std::isfinite(amplitude)) detail::time_law_error(where, "the amplitude must be finite");
  if (!(period > Real(0)) || !std::isfinite(period))
    detail::time_law_error(where, "the period must be positive and finite (it is " + detail::law_number(period) + ")");
  if (!std::isfinite(phase)) detail::time_law_error(where, "the phase must be finite");
  if (!(ramp_periods >= Real(0)) || !std::isfinite(ramp_periods))
    detail::time_law_error(where, "the ramp must be a finite number of periods >= 0 (it is " +
                                      detail::law_number(ramp_periods) + ")");
  if (!std::isfinite(start)) detail::time_law_error(where, "the start time must be finite");
  TimeLaw law = no_motion();
  law.kind = TimeLawKind::sinusoid;
  const Real omega = Real(2) * std::numbers::pi_v<Real> / period;
  law.sinusoid = {amplitude, omega, phase, ramp_periods * period, start};
  return law;
}

// The values a law takes over all times t >= 0: [lowest, highest], or bounded = false where q
// grows without bound (a constant non-zero rate). A prescribed wall's swept box is made of them
// (rigid_motion.hpp: swept_box), and the fluid far from every box skips its wall walk. Exact: a
// sinusoid stays within its amplitude (the ramp r is within [0, 1], and q = 0 before t_s); a
// table's spline is the knots' values and, on each interval, the cubic's turning points (the
// roots of q' = 0 there). Host only: a table's knots must be in host memory.
struct LawRange {
  bool bounded;
  Real lowest, highest;
};

inline LawRange value_range(const TimeLaw& law) {
  switch (law.kind) {
    case TimeLawKind::constant_rate:
      return law.constant_rate.rate == Real(0) ? LawRange{true, Real(0), Real(0)} : LawRange{false, Real(0), Real(0)};
    case TimeLawKind::sinusoid: {
      const Real a = std::abs(law.sinusoid.amplitude);
      return {true, -a, a};
    }
    case TimeLawKind::table: {
      const View<const TableKnot>& k = law.table.knots;
      if (k.size() == 0) return {true, Real(0), Real(0)};
      LawRange r{true, k[0].value, k[0].value};
      const auto take = [&](Real q) { r.lowest = std::min(r.lowest, q), r.highest = std::max(r.highest, q); };
      for (Index i = 0; i + 1 < k.size(); ++i) {
        take(k[i + 1].value);
        // q' on [t_i, t_i+1] in b = (t - t_i)/h: (m1 - m0) h/2 b² + m0 h b + (q1 - q0)/h - (2 m0 + m1) h/6.
        const Real h = k[i + 1].time - k[i].time, m0 = k[i].second_derivative, m1 = k[i + 1].second_derivative;
        const Real qa = (m1 - m0) * h / Real(2), qb = m0 * h,
                   qc = (k[i + 1].value - k[i].value) / h - (Real(2) * m0 + m1) * h / Real(6);
        Real roots[2];
        int n = 0;
        if (qa == Real(0)) {
          if (qb != Real(0)) roots[n++] = -qc / qb;
        } else if (const Real disc = qb * qb - Real(4) * qa * qc; disc >= Real(0)) {
          roots[n++] = (-qb + std::sqrt(disc)) / (Real(2) * qa);
          roots[n++] = (-qb - std::sqrt(disc)) / (Real(2) * qa);
        }
        for (int j = 0; j < n; ++j)
          if (roots[j] > Real(0) && roots[j] < Real(1)) take(law.table(k[i].time + roots[j] * h).value);
      }
      return r;
    }
    default: return {true, Real(0), Real(0)};
  }
}

// A table law over knots already in memory (MotionTable::law builds it).
inline TimeLaw table_law(View<const TableKnot> knots) {
  TimeLaw law = no_motion();
  law.kind = TimeLawKind::table;
  law.table = {knots};
  return law;
}

}  // namespace unisph
