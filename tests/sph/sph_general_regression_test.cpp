// The short form and the general form of the same case give the same observables (issue 21,
// "Regression"), on par, double:
//  * the collapsing column (column_collapse_2d.toml against column_collapse_general_2d.toml: the
//    same particles, less a few out of any fluid particle's reach): the front within 0.5 %;
//  * the 2D dam break in a tank of 215 x 215 dx (both forms then make the same particles): the
//    0.2 H probe's first crossing of 0.2, its mean over t sqrt(g/H) in [3.5, 5] and the front,
//    each within 0.5 %;
//  * the 2D dam break itself (dambreak_2d.toml against dambreak_general_2d.toml): its tank, 5.366 H,
//    is not a whole number of dx, so the general form's far wall lies on the lattice (its first
//    layer 0.36 dx past the face instead of 0.5 dx): the crossing and the front within 0.5 %;
//    the window mean is printed (2.3 % apart at H/40: the mean moves by 1.3 % when only the
//    output interval, which shortens steps, changes; docs/sph.md "The general form").
// (The hydrostatic tank is compared state by state in test_sph_general.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "unisph/solver/case_file.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"

using namespace unisph;
using namespace unisph::sph;

namespace {

struct Series {
  std::vector<double> t, probe, front;

  double first_crossing(double level) const {
    for (std::size_t k = 1; k < t.size(); ++k)
      if (probe[k - 1] <= level && probe[k] > level)
        return t[k - 1] + (level - probe[k - 1]) / (probe[k] - probe[k - 1]) * (t[k] - t[k - 1]);
    return std::nan("");
  }
  // The time average (trapezoids between samples) over [a, b].
  double window_mean(double a, double b) const {
    double sum = 0, span = 0;
    for (std::size_t k = 1; k < t.size(); ++k) {
      const double lo = std::max(a, t[k - 1]), hi = std::min(b, t[k]);
      if (!(hi > lo)) continue;
      const auto at = [&](double x) { return probe[k - 1] + (probe[k] - probe[k - 1]) * (x - t[k - 1]) / (t[k] - t[k - 1]); };
      sum += 0.5 * (at(lo) + at(hi)) * (hi - lo);
      span += hi - lo;
    }
    return sum / span;
  }
  double front_at(double time) const {
    for (std::size_t k = 1; k < t.size(); ++k)
      if (t[k] >= time) return front[k - 1] + (front[k] - front[k - 1]) * (time - t[k - 1]) / (t[k] - t[k - 1]);
    return std::nan("");
  }
};

std::string file_text(const std::string& file) {
  std::ifstream in(std::string(UNISPH_CASES_DIR) + "/" + file);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The text with every `from` replaced by `to`.
std::string replaced_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) text.replace(at, from.size(), to);
  return text;
}

Series run(const std::string& file, double until, const std::string& text = {}) {
  CaseDescription c = text.empty() ? read_case_file(std::string(UNISPH_CASES_DIR) + "/" + file) : parse_case(text, file);
  // Both forms with the mirror's wall term in the continuity equation: the comparison is of the
  // forms' particles, and with the mirror the two runs stay on one trajectory after the impact.
  // With the dam-break cases' "kernel_sum" the window mean of one form alone moved by 2.2 % and
  // its first crossing by 6 % with the output interval (docs/validation.md, "The continuity
  // equation's wall term"), beyond this test's 0.5 %.
  c.wall_continuity = "mirror";
  WeaklyCompressibleSolver<double, 2> solver(c, PolicyKind::par);
  Series s;
  const auto record = [&] {
    const ObserverSample o = solver.observe();
    s.t.push_back(o.time / c.time_scale);
    s.probe.push_back(o.probe_pressure.empty() ? 0.0 : o.probe_pressure[0] / c.pressure_scale);
    s.front.push_back(o.front / c.length_scale);
  };
  record();
  while (solver.time() < until * c.time_scale * (1 - 1e-12)) {
    solver.advance(until * c.time_scale);
    record();
  }
  return s;
}

double relative(double general, double short_form) { return std::abs(general / short_form - 1); }

}  // namespace

// Crossing, window mean and front of the two runs; the mean checked only where `check_mean`.
void compare_dam_breaks(const Series& a, const Series& b, const char* what, bool check_mean) {
  const double crossing = relative(b.first_crossing(0.2), a.first_crossing(0.2));
  const double mean = relative(b.window_mean(3.5, 5.0), a.window_mean(3.5, 5.0));
  const double front = relative(b.front_at(1.5), a.front_at(1.5));
  std::printf("[ measured ] %s, general against short form: first crossing of 0.2 at 0.2 H %.4f / %.4f (%.3f %%), "
              "mean over [3.5, 5] %.4f / %.4f (%.3f %%%s), front at t* = 1.5 %.4f / %.4f (%.3f %%); bound 0.5 %%\n",
              what, b.first_crossing(0.2), a.first_crossing(0.2), 100 * crossing, b.window_mean(3.5, 5.0),
              a.window_mean(3.5, 5.0), 100 * mean, check_mean ? "" : ", not bounded", b.front_at(1.5), a.front_at(1.5), 100 * front);
  EXPECT_LT(crossing, 0.005);
  if (check_mean) EXPECT_LT(mean, 0.005);
  EXPECT_LT(front, 0.005);
}

TEST(HostGeneralRegression, DamBreakOnTheLatticeInTheGeneralFormMatchesTheShortForm) {
  // 5.375 = 215 dx at H/40: the tank (and the probes on its far wall) on the lattice.
  const auto on_lattice = [](const std::string& file) {
    return replaced_all(replaced_all(replaced_all(file_text(file), "5.366", "5.375"), "5.466", "5.475"), "5.566", "5.575");
  };
  const Series a = run("dambreak_2d.toml", 5.0, on_lattice("dambreak_2d.toml"));
  const Series b = run("dambreak_general_2d.toml", 5.0, on_lattice("dambreak_general_2d.toml"));
  // With unisph::Real = float (UNISPH_SINGLE_PRECISION) the shapes' lattice is not the short
  // form's to the last bit, so the sets differ and the mean is only reported (0.97 % there).
  compare_dam_breaks(a, b, "dam break in a tank of 215 dx", sizeof(Real) == 8);
}

TEST(HostGeneralRegression, DamBreakInTheGeneralFormMatchesTheShortForm) {
  const Series a = run("dambreak_2d.toml", 5.0), b = run("dambreak_general_2d.toml", 5.0);
  compare_dam_breaks(a, b, "dam break (5.366 H: the far wall off the lattice)", false);
}

TEST(HostGeneralRegression, CollapsingColumnInTheGeneralFormMatchesTheShortForm) {
  const Series a = run("column_collapse_2d.toml", 2.5), b = run("column_collapse_general_2d.toml", 2.5);
  for (double T : {1.0, 1.8, 2.5}) {
    const double front = relative(b.front_at(T), a.front_at(T));
    std::printf("[ measured ] collapsing column, general against short form: z/L at T = %.1f %.6f / %.6f (%.2e relative; "
                "bound 0.5 %%)\n", T, b.front_at(T), a.front_at(T), front);
    EXPECT_LT(front, 0.005);
  }
}
