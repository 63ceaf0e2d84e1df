// Validation of the weakly compressible SPH solver against experiments (label `validation`).
// Each test runs a case from cases/ on `par` in double and prints its measured figure beside
// its bound. The experimental series are in tests/data/validation/ (see its README).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "unisph/solver/case_file.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"

using namespace unisph;
using namespace unisph::sph;

namespace {

struct Series {
  std::vector<double> t, y;
  // Linear interpolation; outside the data: NaN.
  double at(double x) const {
    if (t.empty() || x < t.front() || x > t.back()) return std::nan("");
    const auto it = std::upper_bound(t.begin(), t.end(), x);
    if (it == t.end()) return y.back();
    const std::size_t k = std::size_t(it - t.begin());
    if (k == 0) return y.front();
    const double w = (x - t[k - 1]) / (t[k] - t[k - 1]);
    return y[k - 1] + w * (y[k] - y[k - 1]);
  }
  // Trapezoidal mean over [a, b] of the piecewise linear series.
  double window_mean(double a, double b) const {
    std::vector<double> xs{a};
    for (double x : t)
      if (x > a && x < b) xs.push_back(x);
    xs.push_back(b);
    double integral = 0;
    for (std::size_t k = 1; k < xs.size(); ++k) integral += 0.5 * (at(xs[k - 1]) + at(xs[k])) * (xs[k] - xs[k - 1]);
    return integral / (b - a);
  }
  // The first time the series exceeds `level`, interpolated linearly from the sample before.
  double first_crossing(double level) const {
    for (std::size_t k = 1; k < t.size(); ++k)
      if (y[k] > level) return t[k - 1] + (level - y[k - 1]) / (y[k] - y[k - 1]) * (t[k] - t[k - 1]);
    return std::nan("");
  }
};

// Issue 23's pressure noise: the series sampled every 0.01 (linear interpolation), minus its
// centred moving average over 25 samples (0.25 time units), its standard deviation over
// [3.5, 5] (scripts/sph_run_metrics.py computes the same).
double pressure_noise(const Series& s) {
  std::vector<double> t, y;
  for (long k = long(std::ceil(s.t.front() / 0.01 - 1e-9)); k * 0.01 <= s.t.back() + 1e-12; ++k) {
    t.push_back(k * 0.01);
    y.push_back(s.at(std::min(k * 0.01, s.t.back())));
  }
  std::vector<double> residual;
  for (std::size_t k = 12; k + 12 < y.size(); ++k) {
    if (t[k] < 3.5 - 1e-9 || t[k] > 5.0 + 1e-9) continue;
    double average = 0;
    for (std::size_t j = k - 12; j <= k + 12; ++j) average += y[j];
    residual.push_back(y[k] - average / 25);
  }
  double mean = 0, variance = 0;
  for (double r : residual) mean += r / double(residual.size());
  for (double r : residual) variance += (r - mean) * (r - mean) / double(residual.size());
  return std::sqrt(variance);
}

// The cells of a validation CSV's data rows: after its '#' comment lines and its header row.
std::vector<std::vector<std::string>> data_rows(const std::string& name) {
  std::ifstream in(std::string(UNISPH_VALIDATION_DATA_DIR) + "/" + name);
  EXPECT_TRUE(in.good()) << name;
  std::vector<std::vector<std::string>> rows;
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      header = false;
      continue;
    }
    std::istringstream fields(line);
    std::vector<std::string> cells;
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

// A two-column series (time, value).
Series read_csv(const std::string& name) {
  Series s;
  for (const auto& row : data_rows(name)) {
    s.t.push_back(std::stod(row.at(0)));
    s.y.push_back(std::stod(row.at(1)));
  }
  return s;
}

// Column k of a CSV against its first column.
Series read_column(const std::string& name, std::size_t k) {
  Series s;
  for (const auto& row : data_rows(name)) {
    s.t.push_back(std::stod(row.at(0)));
    s.y.push_back(std::stod(row.at(k)));
  }
  return s;
}

// A CSV of one index column and several record columns (empty cells: a record that ended).
struct Records {
  std::vector<long long> index;
  std::vector<std::vector<double>> values;  // per row, the records' values (NaN where a record ended)
};
Records read_records(const std::string& name) {
  Records r;
  for (const auto& row : data_rows(name)) {
    r.index.push_back(std::stoll(row.at(0)));
    std::vector<double> values;
    for (std::size_t k = 1; k < row.size(); ++k) values.push_back(row[k].empty() ? std::nan("") : std::stod(row[k]));
    r.values.push_back(values);
  }
  return r;
}
std::pair<double, double> finite_range(const std::vector<double>& v) {
  double lo = INFINITY, hi = -INFINITY;
  for (double x : v)
    if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
  return {lo, hi};
}

CaseDescription load(const std::string& name) { return read_case_file(std::string(UNISPH_CASES_DIR) + "/" + name); }

struct RunRecord {
  std::vector<ObserverSample> samples;
  std::uint64_t acoustic_steps = 0;
  Index fluid = 0;
};

template <class T, int D>
RunRecord run_case(const CaseDescription& c, double end, PolicyKind kind = PolicyKind::par,
             std::vector<Vec<T, D>>* initial = nullptr, std::vector<Vec<T, D>>* final_positions = nullptr) {
  WeaklyCompressibleSolver<T, D> solver(c, kind);
  auto by_id = [&] {
    auto x = solver.fluid_body().positions().to_vector();
    auto id = solver.fluid_body().particles().ids().to_vector();
    std::vector<Vec<T, D>> out(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) out[id[i]] = x[i];
    return out;
  };
  if (initial) *initial = by_id();
  RunRecord run;
  run.fluid = solver.fluid_count();
  run.samples.push_back(solver.observe());
  while (solver.time() < end * (1 - 1e-12)) {
    solver.advance(end);
    run.samples.push_back(solver.observe());
  }
  run.acoustic_steps = solver.acoustic_steps();
  if (final_positions) *final_positions = by_id();
  return run;
}

Series front_series(const RunRecord& run, const CaseDescription& c) {
  Series s;
  for (const auto& o : run.samples) {
    s.t.push_back(o.time / c.time_scale);
    s.y.push_back(o.front / c.length_scale);
  }
  return s;
}
Series probe_series(const RunRecord& run, const CaseDescription& c, std::size_t probe) {
  Series s;
  for (const auto& o : run.samples) {
    s.t.push_back(o.time / c.time_scale);
    s.y.push_back(o.probe_pressure[probe] / c.pressure_scale);
  }
  return s;
}

}  // namespace

// Issue 23's bands for the collapsing column, founded on the experiments and on Koshizuka & Oka's
// own MPS run (docs/validation.md): the front at T = 1.8 without a time shift, then after one
// best-fit time shift (the experiments' gates opened over a finite time) the RMS deviation from
// each experiment series, and the two resolutions against each other.
TEST(HostValidation, ColumnCollapse) {
  const CaseDescription coarse = load("column_collapse_2d.toml");
  CaseDescription fine = coarse;
  fine.dx = coarse.dx / 2;
  const RunRecord run40 = run_case<double, 2>(coarse, coarse.end_time);
  const RunRecord run80 = run_case<double, 2>(fine, fine.end_time);
  const Series z40 = front_series(run40, coarse), z80 = front_series(run80, fine);
  const std::pair<const char*, Series> experiments[] = {
      {"Martin & Moyce a = 1.125 in", read_csv("martin_moyce_1952_a1.125in.csv")},
      {"Martin & Moyce a = 2.25 in", read_csv("martin_moyce_1952_a2.25in.csv")},
      {"Koshizuka & Oka", read_csv("koshizuka_oka_1996_experiment.csv")}};
  // RMS of z_sim(T + shift) / z_exp(T) - 1 over the experiment's samples in [0.8, 2.5].
  const auto rms = [](const Series& run, const Series& e, double shift) {
    double sum = 0;
    int n = 0;
    for (std::size_t k = 0; k < e.t.size(); ++k) {
      if (e.t[k] < 0.8 || e.t[k] > 2.5) continue;
      const double z = run.at(e.t[k] + shift);
      if (std::isnan(z)) continue;
      sum += (z / e.y[k] - 1) * (z / e.y[k] - 1);
      ++n;
    }
    return n > 0 ? std::sqrt(sum / n) : std::nan("");
  };
  for (const auto* run : {&z40, &z80}) {
    const char* name = run == &z40 ? "40" : "80";
    const double at_1_8 = run->at(1.8);
    std::printf("[ measured ] column collapse L/dx = %s: z/L at T = 1.8 = %.3f without time shift (band [2.30, 2.50]; "
                "Koshizuka & Oka's MPS 2.41, the experiments 2.09-2.12)\n",
                name, at_1_8);
    EXPECT_GE(at_1_8, 2.30);
    EXPECT_LE(at_1_8, 2.50);
    // One shift for all series: the one that makes the worst series' RMS smallest, |shift| <= 0.3.
    double best_shift = 0, best = 1e9;
    for (int k = -300; k <= 300; ++k) {
      double worst = 0;
      for (const auto& [label, e] : experiments) worst = std::max(worst, rms(*run, e, k * 0.001));
      if (worst < best) best = worst, best_shift = k * 0.001;
    }
    for (const auto& [label, e] : experiments) {
      const double r = rms(*run, e, best_shift);
      std::printf("[ measured ] column collapse L/dx = %s: shifted by %+.3f, RMS deviation from %s %.2f %% over T in "
                  "[0.8, 2.5] (band 5 %%)\n",
                  name, best_shift, label, 100 * r);
      EXPECT_LE(r, 0.05) << label;
    }
    EXPECT_LE(std::abs(best_shift), 0.3);
  }
  double worst = 0;
  for (std::size_t k = 0; k < z40.t.size(); ++k) {
    if (z40.t[k] < 0.8 || z40.t[k] > 2.5) continue;
    worst = std::max(worst, std::abs(z40.y[k] - z80.at(z40.t[k])) / z80.at(z40.t[k]));
  }
  std::printf("[ measured ] column collapse: L/dx = 40 and 80 differ by at most %.2f %% (band 3 %%); acoustic steps %llu and %llu\n",
              100 * worst, (unsigned long long)run40.acoustic_steps, (unsigned long long)run80.acoustic_steps);
  EXPECT_LE(worst, 0.03);
}

// The probes of cases/dambreak_2d.toml by name.
std::size_t probe_index(const CaseDescription& c, const std::string& name) {
  for (std::size_t k = 0; k < c.probes.size(); ++k)
    if (c.probes[k].name == name) return k;
  ADD_FAILURE() << "no probe " << name;
  return 0;
}

// Issue 23's dam-break bands that the 2-core CPU checks at H/40 (the finer resolutions run on the
// GPU: scripts/sph_validation_gpu.sh and scripts/sph_bands.py). The point probes carry the
// fluid's kernel; the `_wide` ones a kernel of 8 dx, as TrixiParticles samples its sensors.
TEST(HostValidation, DamBreakWallPressure) {
  const CaseDescription c = load("dambreak_2d.toml");
  const RunRecord run = run_case<double, 2>(c, c.end_time);
  const Series p = probe_series(run, c, probe_index(c, "wall_0.2H"));
  const double crossing = p.first_crossing(0.2);
  const Series buchner = read_csv("buchner_2002_wall_pressure.csv");
  std::printf("[ measured ] dam break H/40: first p/(rho g H) > 0.2 at 0.2 H at t sqrt(g/H) = %.3f (band [2.40, 2.70]; "
              "Buchner %.3f)\n",
              crossing, buchner.first_crossing(0.2));
  EXPECT_GE(crossing, 2.40);
  EXPECT_LE(crossing, 2.70);
  // Beside Lobovsky et al.'s sensors (digitised series); their bands are at H/160 and H/320 (GPU).
  const std::pair<const char*, const char*> sensors[] = {{"0.01H", "lobovsky_2014_sensor1.csv"},
                                                         {"0.1H", "lobovsky_2014_sensor3.csv"},
                                                         {"0.267H", "lobovsky_2014_sensor4.csv"}};
  for (const auto& [height, file] : sensors) {
    const Series measured = read_csv(file);
    for (const char* kind : {"", "_wide"}) {
      const Series simulated = probe_series(run, c, probe_index(c, std::string("wall_") + height + kind));
      std::printf("[ measured ] dam break H/40: probe wall_%s%s: mean over [3.5, 5] %.4f, first p* > 0.2 at %.3f; "
                  "Lobovsky (digitised) %.4f, %.3f\n",
                  height, kind, simulated.window_mean(3.5, 5.0), simulated.first_crossing(0.2),
                  measured.window_mean(3.5, 5.0), measured.first_crossing(0.2));
    }
  }
  // Conservation over the whole run.
  const double e0 = run.samples.front().kinetic_energy + run.samples.front().potential_energy;
  double largest = 0;
  for (const auto& s : run.samples) {
    largest = std::max(largest, (s.kinetic_energy + s.potential_energy) / e0);
    EXPECT_EQ(s.mass, run.samples.front().mass);
  }
  std::printf("[ measured ] dam break to t = %.0f: largest mechanical energy / initial = %.5f (bound 1.005); mass "
              "constant; %llu acoustic steps\n",
              c.end_time, largest, (unsigned long long)run.acoustic_steps);
  EXPECT_LE(largest, 1.005);
}

// Issue 23's bands that the method does not meet yet at H/40 (docs/validation.md, "Issue 23"): the
// 0.2 H window mean within 10 % of Buchner's, the pressure noise at every probe at most 1.5 times
// TrixiParticles' WCSPH reference at H/40, and no dip below -0.2 before the impact. An entry of
// its own (label `open`), reported by scripts/test.sh beside the gate.
TEST(HostValidation, DamBreakWindowMeanNoiseAndDip) {
  const CaseDescription c = load("dambreak_2d.toml");
  const RunRecord run = run_case<double, 2>(c, 6.0);
  // No dip below -0.2 before the impact, at any probe.
  for (const ProbeDescription& probe : c.probes) {
    const Series s = probe_series(run, c, probe_index(c, probe.name));
    const double impact = s.first_crossing(0.2);
    double lowest = 0;
    for (std::size_t k = 0; k < s.t.size() && s.t[k] < impact; ++k) lowest = std::min(lowest, s.y[k]);
    std::printf("[ measured ] dam break H/40: probe %s: lowest p/(rho g H) before the impact %.3f (band >= -0.2)\n",
                probe.name.c_str(), lowest);
    EXPECT_GE(lowest, -0.2) << probe.name;
  }

  const Series buchner = read_csv("buchner_2002_wall_pressure.csv");
  const double reference = buchner.window_mean(3.5, 5.0);
  for (const char* kind : {"", "_wide"}) {
    const double mean = probe_series(run, c, probe_index(c, std::string("wall_0.2H") + kind)).window_mean(3.5, 5.0);
    std::printf("[ measured ] dam break H/40: probe wall_0.2H%s: mean over [3.5, 5] %.4f, Buchner %.4f: %+.1f %% (band "
                "+-10 %%)\n",
                kind, mean, reference, 100 * (mean / reference - 1));
    if (*kind == 0) EXPECT_NEAR(mean / reference, 1.0, 0.10);
  }
  // TrixiParticles' WCSPH at H/40, sensors P1, P3, P4 (0.01, 0.1, 0.267 H); 0.2 H linearly between.
  const double n1 = pressure_noise(read_column("trixiparticles_reference_wcsph_H40.csv", 1));
  const double n3 = pressure_noise(read_column("trixiparticles_reference_wcsph_H40.csv", 3));
  const double n4 = pressure_noise(read_column("trixiparticles_reference_wcsph_H40.csv", 4));
  const std::pair<const char*, double> reference_noise[] = {
      {"0.01H", n1}, {"0.1H", n3}, {"0.2H", n3 + (0.2 - 0.1) / (0.2667 - 0.1) * (n4 - n3)}, {"0.267H", n4}};
  for (const auto& [height, peer] : reference_noise)
    for (const char* kind : {"", "_wide"}) {
      const double noise = pressure_noise(probe_series(run, c, probe_index(c, std::string("wall_") + height + kind)));
      std::printf("[ measured ] dam break H/40: probe wall_%s%s: pressure noise %.4f, TrixiParticles' WCSPH %.4f: %.2f "
                  "times (band 1.5)\n",
                  height, kind, noise, peer, noise / peer);
      EXPECT_LE(noise, 1.5 * peer) << height << kind;
    }
}

// The same case in SPHinXsys, the method's reference implementation: its regression records of
// the water's mechanical energy and of the 0.2 H probe (tests/data/validation/README.md), sampled
// every 200 advection steps of its loop, which keeps every acoustic step whole. Run with that loop
// (time.last_acoustic_step = "full"), the samples are compared step for step.
void compare_with_sphinxsys_records(const std::string& free_surface_density) {
  CaseDescription c = load("dambreak_2d.toml");
  c.last_acoustic_step = "full";
  c.free_surface_density = free_surface_density;
  c.density_method = "summation";  // SPHinXsys' scheme, not the case file's continuity density
  c.continuity_dissipation = true;
  c.density_diffusion = 0;
  const char* form = free_surface_density.c_str();
  const RunRecord run = run_case<double, 2>(c, c.end_time);
  const Records energy = read_records("sphinxsys_2d_dambreak_energy.csv");
  const Records pressure = read_records("sphinxsys_2d_dambreak_pressure.csv");
  const double e0 = run.samples.front().kinetic_energy + run.samples.front().potential_energy;
  // SPHinXsys writes its record k >= 1 after the acoustic steps of its advection step 200 k,
  // counted from 0: after 200 k + 1 of them, which is our sample 200 k + 1.
  const auto sample = [&](long long step) { return std::size_t(step == 0 ? 0 : step + 1); };
  // Up to step 1600 (t sqrt(g/H) about 7.3): the impact and the run-up. After it, when the
  // plunging wave falls back into the water, the energy drops in steps whose timing differs
  // between SPHinXsys' own records by up to 7 %; reported only.
  constexpr long long bounded_until = 1600;
  double worst_bounded = 0, worst = 0;
  long long worst_step = 0;
  int compared = 0;
  for (std::size_t k = 0; k < energy.index.size(); ++k) {
    const std::size_t i = sample(energy.index[k]);
    if (i >= run.samples.size()) break;
    const double e = (run.samples[i].kinetic_energy + run.samples[i].potential_energy) / e0;
    const auto [lo, hi] = finite_range(energy.values[k]);
    const double outside = std::max({0.0, e - hi, lo - e}) / e;
    if (energy.index[k] <= bounded_until) worst_bounded = std::max(worst_bounded, outside);
    if (outside >= worst) worst = outside, worst_step = energy.index[k];
    ++compared;
  }
  std::printf("[ measured ] dam break, SPHinXsys' loop, free_surface_density = %s: mechanical energy / initial beyond the range of SPHinXsys' %zu "
              "records by at most %.2f %% up to advection step %lld (bound 1.5 %%), %.2f %% over all %d samples (at "
              "step %lld)\n",
              form, energy.values.front().size(), 100 * worst_bounded, bounded_until, 100 * worst, compared, worst_step);
  int inside = 0, samples = 0;
  std::array<double, 4> at_600{};
  std::printf("[ measured ] dam break, SPHinXsys' loop, free_surface_density = %s, sample by sample: advection step, t sqrt(g/H), E / E(0) and "
              "SPHinXsys' range, p/(rho g H) at 0.2 H and SPHinXsys' range\n",
              form);
  for (std::size_t k = 0; k < pressure.index.size() && k < energy.index.size(); ++k) {
    const std::size_t i = sample(pressure.index[k]);
    if (i >= run.samples.size()) break;
    const double p = run.samples[i].probe_pressure[0] / c.pressure_scale;
    const auto [lo, hi] = finite_range(pressure.values[k]);
    const auto [e_lo, e_hi] = finite_range(energy.values[k]);
    std::printf("[ measured ]   %5lld %7.3f   %.4f  [%.4f, %.4f]   %6.3f  [%6.3f, %6.3f]\n", pressure.index[k],
                run.samples[i].time / c.time_scale,
                (run.samples[i].kinetic_energy + run.samples[i].potential_energy) / e0, e_lo, e_hi, p, lo, hi);
    ++samples;
    if (p >= lo - 0.05 && p <= hi + 0.05) ++inside;
    if (pressure.index[k] == 600) at_600 = {run.samples[i].time / c.time_scale, p, lo, hi};
  }
  // Just after the impact at the foot of the wall: has the pressure at 0.2 H risen yet?
  std::printf("[ measured ] dam break, SPHinXsys' loop, free_surface_density = %s: at advection step 600 (t sqrt(g/H) = %.3f) p/(rho g H) at 0.2 H "
              "= %.3f, SPHinXsys' records %.3f .. %.3f\n",
              form, at_600[0], at_600[1], at_600[2], at_600[3]);
  std::printf("[ measured ] dam break, SPHinXsys' loop, free_surface_density = %s: %d of %d samples of the 0.2 H probe within 0.05 of the range of "
              "SPHinXsys' records (reported; single samples carry the probe's acoustic noise)\n",
              form, inside, samples);
  EXPECT_GE(compared, 20);
  EXPECT_LE(worst_bounded, 0.015);
}

// Both forms of the free-surface density (density_summation.hpp): the records were made with
// SPHinXsys' earlier one, "carried"; unisph's cases take "reference".
TEST(HostValidation, DamBreakAgainstSphinxsysRecords) {
  compare_with_sphinxsys_records("reference");
  compare_with_sphinxsys_records("carried");
}

TEST(HostValidation, HydrostaticTank) {
  const CaseDescription c = load("hydrostatic_2d.toml");
  std::vector<Vec<double, 2>> x0, x1;
  const RunRecord run = run_case<double, 2>(c, c.end_time, PolicyKind::par, &x0, &x1);
  const double rho_g_h = c.density * c.gravity * c.column[1];
  const double depths[] = {0.25, 0.5, 0.75};
  for (std::size_t k = 0; k < 3; ++k) {
    const Series p = probe_series(run, c, k);
    const double mean = p.window_mean(c.end_time - 5, c.end_time) * c.pressure_scale;
    const double expected = rho_g_h * depths[k];
    if (k == 0) {
      std::printf("[ measured ] hydrostatic: depth 0.25 H: p = %.5f, rho g depth = %.5f, error %.5f rho g H (bound 0.01)\n",
                  mean, expected, std::abs(mean - expected) / rho_g_h);
      EXPECT_LE(std::abs(mean - expected), 0.01 * rho_g_h);
    } else {
      std::printf("[ measured ] hydrostatic: depth %.2f H: p = %.5f, rho g depth = %.5f, error %.2f %% (bound 2 %%)\n",
                  depths[k], mean, expected, 100 * std::abs(mean / expected - 1));
      EXPECT_LE(std::abs(mean / expected - 1), 0.02);
    }
  }
  const ObserverSample& last = run.samples.back();
  // Potential energy measured from the floor (y = 0): sum m g y.
  std::printf("[ measured ] hydrostatic: kinetic / potential energy at t = %.0f: %.2e (bound 1e-3)\n", c.end_time,
              last.kinetic_energy / last.potential_energy);
  EXPECT_LT(last.kinetic_energy, 1e-3 * last.potential_energy);
  std::size_t moved = 0;
  for (std::size_t i = 0; i < x0.size(); ++i) moved += norm(x1[i] - x0[i]) >= c.dx;
  const double fraction = 1.0 - double(moved) / double(x0.size());
  std::printf("[ measured ] hydrostatic: %.2f %% of the particles moved less than dx (bound 99 %%)\n", 100 * fraction);
  EXPECT_GE(fraction, 0.99);
}

// Issue 23, item 2: the tank started without the settling stage keeps 99 % of its particles within
// dx, its probes within 2 % and its kinetic energy below 1e-3 of the potential, from water relaxed
// in its box before the start (cases/hydrostatic_relaxed_2d.toml: fill = "relaxed"). The square
// lattice is a saddle of the pair pressure force at h = 1.3 dx, and water started on it drifts
// (docs/validation.md, "The hydrostatic tank without settling"): the next entry reports it.
TEST(HostValidation, HydrostaticTankWithoutSettling) {
  const CaseDescription c = load("hydrostatic_relaxed_2d.toml");
  ASSERT_EQ(c.settling_time, 0.0);
  std::vector<Vec<double, 2>> x0, x1;
  const RunRecord run = run_case<double, 2>(c, c.end_time, PolicyKind::par, &x0, &x1);
  const double rho_g_h = c.density * c.gravity * c.free_surface;
  const double depths[] = {0.25, 0.5, 0.75};
  for (std::size_t k = 0; k < 3; ++k) {
    const double mean = probe_series(run, c, k).window_mean(c.end_time - 5, c.end_time) * c.pressure_scale;
    const double expected = rho_g_h * depths[k];
    std::printf("[ measured ] hydrostatic, relaxed, without settling: depth %.2f H: p = %.5f, rho g depth = %.5f, error %.2f %% "
                "(%.5f rho g H; bound %s)\n",
                depths[k], mean, expected, 100 * std::abs(mean / expected - 1), std::abs(mean - expected) / rho_g_h,
                k == 0 ? "0.01 rho g H" : "2 %");
    if (k == 0) EXPECT_LE(std::abs(mean - expected), 0.01 * rho_g_h);
    else EXPECT_LE(std::abs(mean / expected - 1), 0.02);
  }
  const ObserverSample& last = run.samples.back();
  std::printf("[ measured ] hydrostatic, relaxed, without settling: kinetic / potential energy at t = %.0f: %.2e (bound 1e-3)\n",
              c.end_time, last.kinetic_energy / last.potential_energy);
  EXPECT_LT(last.kinetic_energy, 1e-3 * last.potential_energy);
  std::size_t moved = 0;
  for (std::size_t i = 0; i < x0.size(); ++i) moved += norm(x1[i] - x0[i]) >= c.dx;
  const double fraction = 1.0 - double(moved) / double(x0.size());
  std::printf("[ measured ] hydrostatic, relaxed, without settling: %.2f %% of %zu particles moved less than dx by t = %.0f "
              "(band 99 %%)\n",
              100 * fraction, x0.size(), c.end_time);
  EXPECT_GE(fraction, 0.99);
}

// The same tank started on the lattice without settling (reported, label `open`: what the relaxed
// start replaces; 29.4 to 30.1 % within dx).
TEST(HostValidation, HydrostaticTankOnTheLatticeWithoutSettling) {
  CaseDescription c = load("hydrostatic_2d.toml");
  c.settling_time = 0;
  std::vector<Vec<double, 2>> x0, x1;
  run_case<double, 2>(c, c.end_time, PolicyKind::par, &x0, &x1);
  std::size_t moved = 0;
  for (std::size_t i = 0; i < x0.size(); ++i) moved += norm(x1[i] - x0[i]) >= c.dx;
  const double fraction = 1.0 - double(moved) / double(x0.size());
  std::printf("[ measured ] hydrostatic on the lattice without settling: %.2f %% of the particles moved less than dx by t = %.0f "
              "(the relaxed start keeps 99 %%)\n",
              100 * fraction, c.end_time);
  EXPECT_GE(fraction, 0.99);
}

TEST(HostValidation, SiMatchesDimensionless) {
  const CaseDescription a = load("dambreak_2d.toml");
  const CaseDescription b = load("dambreak_2d_si.toml");
  WeaklyCompressibleSolver<double, 2> dimensionless(a, PolicyKind::seq), si(b, PolicyKind::seq);
  while (dimensionless.acoustic_steps() < 200) dimensionless.advance(1e9);
  while (si.acoustic_steps() < dimensionless.acoustic_steps()) si.advance(1e9);
  ASSERT_EQ(si.acoustic_steps(), dimensionless.acoustic_steps());
  const double time_difference = std::abs(si.time() / b.time_scale - dimensionless.time()) / dimensionless.time();
  auto xa = dimensionless.fluid_body().positions().to_vector(), xb = si.fluid_body().positions().to_vector();
  auto ia = dimensionless.fluid_body().particles().ids().to_vector(), ib = si.fluid_body().particles().ids().to_vector();
  auto pa = dimensionless.fluid_body().particles().variable<double>("Pressure").to_vector();
  auto pb = si.fluid_body().particles().variable<double>("Pressure").to_vector();
  std::vector<std::size_t> index_b(xb.size());
  for (std::size_t i = 0; i < xb.size(); ++i) index_b[ib[i]] = i;
  double position = 0, pressure = 0, largest_pressure = 0;
  for (std::size_t i = 0; i < xa.size(); ++i) {
    const std::size_t j = index_b[ia[i]];
    position = std::max(position, norm(xa[i] - xb[j] * (1 / b.length_scale)));
    pressure = std::max(pressure, std::abs(pa[i] - pb[j] / b.pressure_scale));
    largest_pressure = std::max(largest_pressure, std::abs(pa[i]));
  }
  position /= a.tank[0];
  pressure /= largest_pressure;
  std::printf("[ measured ] SI vs dimensionless after %llu acoustic steps (double, seq): time %.2e, positions %.2e, "
              "pressures %.2e relative (bound 1e-6)\n",
              (unsigned long long)si.acoustic_steps(), time_difference, position, pressure);
  EXPECT_LE(time_difference, 1e-6);
  EXPECT_LE(position, 1e-6);
  EXPECT_LE(pressure, 1e-6);
}
