#pragma once
// Analysis of measured time series (host): the least-squares fit of a sinusoid of known period,
// and Goda & Suzuki's (1976) two-gauge separation of incident and reflected waves on series.
// Arguments that cannot give an answer (series of different lengths, too few samples, a
// period or spacing that is not positive, samples that do not determine the sinusoid, gauges
// a multiple of half a wave length apart) throw a one-line unisph::Error.

#include <span>
#include <vector>

#include "unisph/motion/linear_waves.hpp"

namespace unisph {

// y(t) ≈ mean + cosine cos ω t + sine sin ω t = mean + amplitude sin(ω t + phase).
struct SinusoidFit {
  double mean;
  double cosine;        // A
  double sine;          // B
  double amplitude;     // sqrt(A² + B²)
  double phase;         // atan2(A, B), radians
  double rms_residual;  // the root mean square of y - fit: how far the series is from a sinusoid
};

// Least squares over the samples (t_i, y_i) with the period given (at least 3 samples). Any
// window and any sampling will do; over whole periods of uniform samples the coefficients are
// the Fourier coefficients of the series at ω = 2π / period.
SinusoidFit fit_sinusoid(std::span<const double> time, std::span<const double> series, double period);

// The same with several periods at once: y(t) ≈ mean + Σ_p (A_p cos ω_p t + B_p sin ω_p t),
// fitted together (the forced response and a free oscillation of another frequency in one
// record: the swaying tank of tests/sph/sph_sloshing_test.cpp). One fit per period, in their
// order, each with the common mean and the whole fit's residual. At least 1 + 2 P samples; a
// window too short to tell the periods apart is an error.
std::vector<SinusoidFit> fit_sinusoids(std::span<const double> time, std::span<const double> series,
                                       std::span<const double> periods);

// The incident and reflected waves of period T from two gauge series sampled at the same times,
// gauge 2 `spacing` beyond gauge 1 in the incident direction, in water of depth d under gravity
// g (k from the dispersion relation): each series is fitted (fit_sinusoid), then separated
// (separate_incident_reflected). The spacing must lie within 0.05 to 0.45 of a wave length
// modulo half a wave length (Goda & Suzuki's range; outside it sin kΔ is small and errors grow).
IncidentReflected<double> two_gauge_reflection(std::span<const double> time, std::span<const double> gauge1,
                                               std::span<const double> gauge2, double period, double spacing,
                                               double depth, double g);

}  // namespace unisph
