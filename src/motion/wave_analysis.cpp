// Sinusoid fits and the two-gauge reflection analysis of time series (host only).
#include "unisph/motion/wave_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "unisph/core/error.hpp"

namespace unisph {

namespace {

std::string text(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

}  // namespace

std::vector<SinusoidFit> fit_sinusoids(std::span<const double> time, std::span<const double> series,
                                       std::span<const double> periods) {
  const std::size_t n = time.size();
  const std::size_t terms = 1 + 2 * periods.size();  // the mean, then cos and sin of each period
  const std::string name = periods.size() == 1 ? "fit_sinusoid" : "fit_sinusoids";
  if (series.size() != n)
    throw Error(name + ": " + std::to_string(n) + " times but " + std::to_string(series.size()) + " values");
  if (periods.empty()) throw Error(name + ": no period given");
  for (double period : periods)
    if (!(period > 0.0) || !std::isfinite(period))
      throw Error(name + ": the period must be positive and finite (it is " + text(period) + ")");
  if (n < terms)
    throw Error(name + ": " + std::to_string(n) + " samples; " +
                (periods.size() == 1 ? std::string("a sinusoid with a mean needs")
                                     : "a mean and " + std::to_string(periods.size()) + " sinusoids need") +
                " at least " + std::to_string(terms));
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(time[i]) || !std::isfinite(series[i]))
      throw Error(name + ": sample " + std::to_string(i) + " is not finite");
  std::vector<double> omega(periods.size());
  for (std::size_t p = 0; p < periods.size(); ++p) omega[p] = 2.0 * std::numbers::pi / periods[p];
  const auto basis_at = [&](double t, std::vector<double>& basis) {
    basis[0] = 1.0;
    for (std::size_t p = 0; p < periods.size(); ++p) {
      basis[1 + 2 * p] = std::cos(omega[p] * t);
      basis[2 + 2 * p] = std::sin(omega[p] * t);
    }
  };
  // Normal equations of the basis (1, cos ω_1 t, sin ω_1 t, ...): M c = r.
  std::vector<std::vector<double>> m(terms, std::vector<double>(terms, 0.0));
  std::vector<double> r(terms, 0.0), basis(terms);
  for (std::size_t i = 0; i < n; ++i) {
    basis_at(time[i], basis);
    for (std::size_t a = 0; a < terms; ++a) {
      r[a] += basis[a] * series[i];
      for (std::size_t b = 0; b < terms; ++b) m[a][b] += basis[a] * basis[b];
    }
  }
  // Gaussian elimination with partial pivoting; a pivot below 1e-12 of the largest diagonal
  // entry means the samples do not determine the coefficients (too short a window for periods
  // this close, or every sample at the same phase).
  double scale = 0.0;
  for (std::size_t a = 0; a < terms; ++a) scale = std::max(scale, m[a][a]);
  std::vector<std::size_t> order(terms);
  for (std::size_t a = 0; a < terms; ++a) order[a] = a;
  for (std::size_t col = 0; col < terms; ++col) {
    std::size_t best = col;
    for (std::size_t row = col + 1; row < terms; ++row)
      if (std::abs(m[order[row]][col]) > std::abs(m[order[best]][col])) best = row;
    std::swap(order[col], order[best]);
    const std::size_t p = order[col];
    if (!(std::abs(m[p][col]) > 1e-12 * scale)) {
      std::string list;
      for (std::size_t k = 0; k < periods.size(); ++k) list += (k ? ", " : "") + text(periods[k]);
      throw Error(name + ": the " + std::to_string(n) + " samples over [" + text(time[0]) + ", " + text(time[n - 1]) +
                  "] do not determine " + (periods.size() == 1 ? "a sinusoid of period " : "sinusoids of periods ") +
                  list + " (too short a window, or every sample at the same phase)");
    }
    for (std::size_t row = col + 1; row < terms; ++row) {
      const std::size_t q = order[row];
      const double factor = m[q][col] / m[p][col];
      for (std::size_t k = col; k < terms; ++k) m[q][k] -= factor * m[p][k];
      r[q] -= factor * r[p];
    }
  }
  std::vector<double> c(terms, 0.0);
  for (std::size_t col = terms; col-- > 0;) {
    const std::size_t p = order[col];
    double v = r[p];
    for (std::size_t k = col + 1; k < terms; ++k) v -= m[p][k] * c[k];
    c[col] = v / m[p][col];
  }
  double squares = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    basis_at(time[i], basis);
    double fit = c[0];
    for (std::size_t a = 1; a < terms; ++a) fit += c[a] * basis[a];
    const double e = series[i] - fit;
    squares += e * e;
  }
  std::vector<SinusoidFit> fits(periods.size());
  for (std::size_t p = 0; p < periods.size(); ++p) {
    SinusoidFit& fit = fits[p];
    fit.mean = c[0];
    fit.cosine = c[1 + 2 * p];
    fit.sine = c[2 + 2 * p];
    fit.amplitude = std::hypot(fit.cosine, fit.sine);
    fit.phase = std::atan2(fit.cosine, fit.sine);
    fit.rms_residual = std::sqrt(squares / double(n));
  }
  return fits;
}

SinusoidFit fit_sinusoid(std::span<const double> time, std::span<const double> series, double period) {
  return fit_sinusoids(time, series, std::span<const double>(&period, 1)).front();
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
