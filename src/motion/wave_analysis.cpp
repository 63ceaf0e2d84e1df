// Sinusoid fits and the two-gauge reflection analysis of time series (host only).
#include "unisph/motion/wave_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>

#include "unisph/core/error.hpp"

namespace unisph {

namespace {

std::string text(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

}  // namespace

SinusoidFit fit_sinusoid(std::span<const double> time, std::span<const double> series, double period) {
  const std::size_t n = time.size();
  if (series.size() != n)
    throw Error("fit_sinusoid: " + std::to_string(n) + " times but " + std::to_string(series.size()) + " values");
  if (!(period > 0.0) || !std::isfinite(period))
    throw Error("fit_sinusoid: the period must be positive and finite (it is " + text(period) + ")");
  if (n < 3) throw Error("fit_sinusoid: " + std::to_string(n) + " samples; a sinusoid with a mean needs at least 3");
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(time[i]) || !std::isfinite(series[i]))
      throw Error("fit_sinusoid: sample " + std::to_string(i) + " is not finite");
  const double omega = 2.0 * std::numbers::pi / period;
  // Normal equations of the basis (1, cos ωt, sin ωt): M c = r.
  double m[3][3] = {}, r[3] = {};
  for (std::size_t i = 0; i < n; ++i) {
    const double basis[3] = {1.0, std::cos(omega * time[i]), std::sin(omega * time[i])};
    for (int a = 0; a < 3; ++a) {
      r[a] += basis[a] * series[i];
      for (int b = 0; b < 3; ++b) m[a][b] += basis[a] * basis[b];
    }
  }
  // Gaussian elimination with partial pivoting; a pivot below 1e-12 of the largest diagonal
  // entry means the samples do not determine the three coefficients.
  const double scale = std::max({m[0][0], m[1][1], m[2][2]});
  int order[3] = {0, 1, 2};
  for (int col = 0; col < 3; ++col) {
    int best = col;
    for (int row = col + 1; row < 3; ++row)
      if (std::abs(m[order[row]][col]) > std::abs(m[order[best]][col])) best = row;
    std::swap(order[col], order[best]);
    const int p = order[col];
    if (!(std::abs(m[p][col]) > 1e-12 * scale))
      throw Error("fit_sinusoid: the " + std::to_string(n) + " samples over [" + text(time[0]) + ", " +
                  text(time[n - 1]) + "] do not determine a sinusoid of period " + text(period) +
                  " (too short a window, or every sample at the same phase)");
    for (int row = col + 1; row < 3; ++row) {
      const int q = order[row];
      const double factor = m[q][col] / m[p][col];
      for (int k = col; k < 3; ++k) m[q][k] -= factor * m[p][k];
      r[q] -= factor * r[p];
    }
  }
  double c[3] = {};
  for (int col = 2; col >= 0; --col) {
    const int p = order[col];
    double v = r[p];
    for (int k = col + 1; k < 3; ++k) v -= m[p][k] * c[k];
    c[col] = v / m[p][col];
  }
  SinusoidFit fit{};
  fit.mean = c[0];
  fit.cosine = c[1];
  fit.sine = c[2];
  fit.amplitude = std::hypot(c[1], c[2]);
  fit.phase = std::atan2(c[1], c[2]);
  double squares = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double e = series[i] - (c[0] + c[1] * std::cos(omega * time[i]) + c[2] * std::sin(omega * time[i]));
    squares += e * e;
  }
  fit.rms_residual = std::sqrt(squares / double(n));
  return fit;
}

IncidentReflected<double> two_gauge_reflection(std::span<const double> time, std::span<const double> gauge1,
                                               std::span<const double> gauge2, double period, double spacing,
                                               double depth, double g) {
  if (gauge1.size() != time.size() || gauge2.size() != time.size())
    throw Error("two_gauge_reflection: " + std::to_string(time.size()) + " times but " + std::to_string(gauge1.size()) +
                " and " + std::to_string(gauge2.size()) + " gauge values");
  if (!(period > 0.0) || !std::isfinite(period))
    throw Error("two_gauge_reflection: the period must be positive and finite (it is " + text(period) + ")");
  if (!(spacing > 0.0) || !std::isfinite(spacing))
    throw Error("two_gauge_reflection: the gauge spacing must be positive and finite (it is " + text(spacing) + ")");
  if (!(depth > 0.0) || !(g > 0.0))
    throw Error("two_gauge_reflection: the depth and gravity must be positive (they are " + text(depth) + " and " +
                text(g) + ")");
  const double k = wave_number_for_period(period, depth, g);
  const double length = 2.0 * std::numbers::pi / k;
  const double fraction = spacing / length - 0.5 * std::floor(2.0 * spacing / length);  // in [0, 0.5)
  if (!(fraction >= 0.05 && fraction <= 0.45))
    throw Error("two_gauge_reflection: the gauges are " + text(spacing / length) + " wave lengths apart (L = " +
                text(length) + "); Goda & Suzuki's method needs 0.05 to 0.45 of a wave length, modulo half a wave length");
  const SinusoidFit one = fit_sinusoid(time, gauge1, period);
  const SinusoidFit two = fit_sinusoid(time, gauge2, period);
  return separate_incident_reflected(one.cosine, one.sine, two.cosine, two.sine, k, spacing);
}

}  // namespace unisph
