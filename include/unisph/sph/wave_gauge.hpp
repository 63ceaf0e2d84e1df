#pragma once
// Wave gauges: the free-surface elevation along vertical lines, from the fluid's kernel sum
// (issue 22, "Measurements"; docs/motion.md, "Measurements and wave absorption").
//
// A gauge is the line through a given point along -gravity ("up"), from a level `bottom` to a
// level `top` (levels are coordinates along up: y when gravity is along -y; the line of a 2D
// gauge is x = const, of a 3D gauge (x, z) = const). It is sampled every `spacing` (dx/4 by
// default, dx/2 at most, the top and bottom included), and at each sample point x the fluid's
// kernel sum
//
//   S(x) = sum_j W(|x - x_j|) V_j,    V_j = m_j / rho_j,
//
// is taken over the fluid particles within the cutoff (a direct search through the fluid's cell
// list, PointNeighbors). S is the fraction of the kernel's support that the fluid fills: 1 deep
// inside the fluid (W integrates to 1), 0 away from it, 1/2 on a flat free surface of a
// continuous fluid. The gauge reports the highest level where S crosses the threshold 1/2,
// interpolated linearly between the two samples around it.
//
// The criterion's bias. On the square lattice (particles at the cell centres of a water column of
// depth d) the sum is not exactly 1 inside (dx^D sigma0 = 1.0105 at a particle in 2D, 0.993 to
// 1.011 between particles at h = 1.3 dx), so the level where it crosses 1/2 is not exactly d: the
// lattice sum gives d - 0.0009 dx on a column of particles and d - 0.0054 dx half-way between two
// columns (2D, a Python sum over the lattice), and test_sph_measurements measures the gauges'
// readings (with the interpolation between samples) within 0.01 dx of d in 2D and 3D. Where the
// surface slopes the kernel sum averages it over the support (radius 2h = 2.6 dx): the reading is
// the local height to within a fraction of dx for gentle slopes (the test: slope 0.2, within
// 0.5 dx), and a crest or trough narrower than the support is flattened. What else to know:
//  * the sum counts fluid particles only. Beside a wall (the floor too) S is about 1/2 inside
//    the water, so a gauge whose bottom lies at the floor sees a second crossing there; the
//    highest crossing is the free surface's. A film thinner than about h reads dry or low.
//  * dry: S < 1/2 at every sample (no water on the line): the elevation is `bottom`.
//    submerged: S >= 1/2 at the top sample (the water is above the line): the elevation is `top`.
//    Both are told by GaugeReading::state; a CSV column holds the elevation alone.
//  * a NaN in the sum (a NaN density or mass near the line) above the surface gives a NaN
//    elevation (state wet).
//  * the search uses the cells of the list's last build (point_neighbors.hpp): measure after the
//    list was rebuilt, as the solver's observers run after its rebuild.
//
// All gauges are sampled in one launch (one thread per sample); measure() then copies the sums
// to the host (a few hundred numbers) and finds each gauge's crossing there.
//
//   WaveGauges<T, 2> gauges(fluid, fluid_cells, kernel, dx, gravity,
//                           {{"x2", {{2.0, 0.0}}, 0.0, 1.0}, {"x3", {{3.0, 0.0}}, 0.0, 1.0}});
//   std::vector<GaugeReading<T>> r = gauges.measure(policy);   // r[g].elevation, r[g].state
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "unisph/core/error.hpp"
#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/sph/point_neighbors.hpp"

namespace unisph::sph {

// One gauge: its name (the CSV column is gauge_<name>), a point of its line (only the part
// across gravity counts) and the levels of the line's ends along -gravity.
template <class T, int D>
struct WaveGaugeLine {
  std::string name;
  Vec<T, D> position;
  T bottom;
  T top;
};

enum class GaugeState : std::uint8_t {
  wet,        // the sum crosses the threshold on the line: the elevation is the crossing
  dry,        // below the threshold at every sample: the elevation is `bottom`
  submerged,  // at or above it at the top sample: the elevation is `top`
};

inline const char* to_string(GaugeState s) {
  switch (s) {
    case GaugeState::wet: return "wet";
    case GaugeState::dry: return "dry";
    case GaugeState::submerged: return "submerged";
  }
  return "?";
}

template <class T>
struct GaugeReading {
  T elevation;  // a level along -gravity
  GaugeState state;
};

// The highest crossing of `threshold` by the sums at the ascending levels (n >= 2): scanning
// down from the top, the first sample with sum >= threshold and the one above it, linearly
// interpolated. The gauges' host side; public for tests.
template <class T>
GaugeReading<T> highest_crossing(const T* levels, const T* sums, Index n, T threshold) {
  if (!(sums[n - 1] < threshold)) {
    if (std::isnan(sums[n - 1])) return {std::numeric_limits<T>::quiet_NaN(), GaugeState::wet};
    return {levels[n - 1], GaugeState::submerged};
  }
  for (Index above = n - 1; above > 0; --above) {
    const Index k = above - 1;
    if (sums[k] < threshold) continue;
    if (std::isnan(sums[k])) return {std::numeric_limits<T>::quiet_NaN(), GaugeState::wet};
    // sums[k] >= threshold > sums[k + 1]
    const T fraction = (sums[k] - threshold) / (sums[k] - sums[k + 1]);
    return {levels[k] + fraction * (levels[k + 1] - levels[k]), GaugeState::wet};
  }
  return {levels[0], GaugeState::dry};
}

template <class T, int D>
class WaveGauges : public UpdateDynamics<WaveGauges<T, D>> {
 public:
  // `fluid_cells`: the fluid's cell list (the one its inner relation walks: inner.cell_list()),
  // with a cutoff at least the kernel's. Samples every spacing_in_dx * dx, at most dx/2.
  // `threshold`: the fraction of the support filled at the surface, 1/2. Throws unisph::Error
  // (one line) for a bad gauge (empty, duplicate or unprintable name, non-finite position,
  // top not above bottom) or bad parameters.
  WaveGauges(FluidVariables<T, D>& fluid, CellLinkedList<T, D>& fluid_cells, WendlandC2Kernel<T, D> kernel, T dx,
             Vec<T, D> gravity, std::vector<WaveGaugeLine<T, D>> lines, T spacing_in_dx = T(0.25),
             T threshold = T(0.5))
      : fluid_(fluid), cells_(fluid_cells), kernel_(kernel), lines_(std::move(lines)), threshold_(threshold),
        samples_("WaveGauges.Samples"), sums_("WaveGauges.KernelSums") {
    const T g = std::sqrt(squared_norm(gravity));
    if (!(g > T(0)) || !(g < std::numeric_limits<T>::infinity()))
      throw Error("wave gauges: gravity must be finite and not zero; it gives the gauges' vertical");
    up_ = gravity * (T(-1) / g);
    if (!(dx > T(0)) || !(dx < std::numeric_limits<T>::infinity()))
      throw Error("wave gauges: dx must be positive and finite (it is " + std::to_string(dx) + ")");
    if (!(spacing_in_dx > T(0)) || !(spacing_in_dx <= T(0.5)))
      throw Error("wave gauges: the sample spacing must be in (0, 0.5] dx (it is " + std::to_string(spacing_in_dx) +
                  " dx)");
    if (!(threshold > T(0)) || !(threshold < T(1)))
      throw Error("wave gauges: the threshold must be in (0, 1) (it is " + std::to_string(threshold) + ")");
    if (!(fluid_cells.grid().cutoff >= kernel.cutoff()))
      throw Error("wave gauges: the cell list's cutoff " + std::to_string(fluid_cells.grid().cutoff) +
                  " is below the kernel's " + std::to_string(kernel.cutoff()));
    const T spacing = spacing_in_dx * dx;
    std::vector<Vec<T, D>> points;
    for (std::size_t g_index = 0; g_index < lines_.size(); ++g_index) {
      const WaveGaugeLine<T, D>& line = lines_[g_index];
      check_line(line, g_index);
      const T count = std::ceil((line.top - line.bottom) / spacing) + T(1);
      if (!(count <= T(1 << 20)))
        throw Error("wave gauge '" + line.name + "': " + std::to_string(count) +
                    " samples from bottom to top; at most 2^20 (a shorter line or a larger dx)");
      const Index n = static_cast<Index>(count);
      const T step = (line.top - line.bottom) / T(n - 1);
      // The line's point across gravity, then up along it.
      const Vec<T, D> foot = line.position - up_ * dot(line.position, up_);
      first_.push_back(Index(points.size()));
      counts_.push_back(n);
      for (Index k = 0; k < n; ++k) {
        const T level = k == n - 1 ? line.top : line.bottom + T(k) * step;
        levels_.push_back(level);
        points.push_back(foot + up_ * level);
      }
    }
    samples_.assign(std::span<const Vec<T, D>>(points.data(), points.size()));
    sums_.resize(samples_.size());
    points_ = std::move(points);
  }

  struct Kernel {
    PointNeighbors<T, D> fluid;
    View<const Vec<T, D>> samples;
    View<const T> mass, density;
    View<T> sums;
    WendlandC2Kernel<T, D> kernel;
    UNISPH_HOST_DEVICE void update(Index k, Real) const {
      const Vec<T, D> x = samples[k];
      T sum = T(0);
      fluid.for_each(x, [&](Index j, T r) { sum += kernel.value(r) * (mass[j] / density[j]); });
      sums[k] = sum;
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  Kernel make_kernel(KernelContext& c) {
    return {PointNeighbors<T, D>::make(c, cells_), c.read(samples_), c.read(fluid_.mass), c.read(fluid_.density),
            c.write(sums_), kernel_};
  }
  // One item per sample of every gauge.
  Index size() const { return samples_.size(); }

  // The kernel sums at every sample (one launch), then each gauge's highest crossing (host).
  template <ExecutionPolicy P>
  std::vector<GaugeReading<T>> measure(P policy) {
    return readings(sums(policy));
  }
  // The two halves of measure(), for samples spread over ranks (each sample's sum taken by the
  // rank that owns its point, then combined): the kernel sum at every sample (one launch, copied
  // to the host; sample_points() order), and each gauge's reading from such sums.
  template <ExecutionPolicy P>
  std::vector<T> sums(P policy) {
    if (lines_.empty()) return {};
    this->exec(policy);
    return sums_.to_vector();
  }
  std::vector<GaugeReading<T>> readings(std::span<const T> sums) const {
    if (sums.size() != levels_.size())
      throw Error("wave gauges: " + std::to_string(sums.size()) + " sums for " + std::to_string(levels_.size()) +
                  " samples");
    std::vector<GaugeReading<T>> out;
    for (std::size_t g = 0; g < lines_.size(); ++g)
      out.push_back(highest_crossing(levels_.data() + first_[g], sums.data() + first_[g], counts_[g], threshold_));
    return out;
  }
  // Every gauge's sample points, gauge after gauge, bottom to top (on the host).
  const std::vector<Vec<T, D>>& sample_points() const { return points_; }

  const std::vector<WaveGaugeLine<T, D>>& lines() const { return lines_; }
  // The observer CSV's columns, in the order of measure()'s readings: gauge_<name>.
  std::vector<std::string> column_names() const {
    std::vector<std::string> names;
    for (const WaveGaugeLine<T, D>& line : lines_) names.push_back("gauge_" + line.name);
    return names;
  }
  // Gauge g's sample levels (ascending) and, after a measure(), its kernel sums there.
  std::vector<T> levels(std::size_t g) const {
    return std::vector<T>(levels_.begin() + first_[g], levels_.begin() + first_[g] + counts_[g]);
  }
  std::vector<T> kernel_sums(std::size_t g) {
    View<const T> sums = sums_.read(MemorySpace::host);
    return std::vector<T>(sums.begin() + first_[g], sums.begin() + first_[g] + counts_[g]);
  }
  // The unit vector along -gravity: levels are coordinates along it.
  const Vec<T, D>& up() const { return up_; }
  T threshold() const { return threshold_; }

 private:
  void check_line(const WaveGaugeLine<T, D>& line, std::size_t index) const {
    const std::string who = "wave gauge " + std::to_string(index) + " '" + line.name + "'";
    if (line.name.empty()) throw Error("wave gauge " + std::to_string(index) + ": the name is empty");
    for (char ch : line.name) {
      const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_' ||
                      ch == '-' || ch == '.';
      if (!ok) throw Error(who + ": the name may hold letters, digits, '_', '-' and '.' only (it names a CSV column)");
    }
    for (std::size_t other = 0; other < index; ++other)
      if (lines_[other].name == line.name) throw Error(who + ": the name is taken by gauge " + std::to_string(other));
    for (int a = 0; a < D; ++a)
      if (!std::isfinite(line.position[a])) throw Error(who + ": the position must be finite");
    if (!std::isfinite(line.bottom) || !std::isfinite(line.top) || !(line.top > line.bottom))
      throw Error(who + ": the top (" + std::to_string(line.top) + ") must be above the bottom (" +
                  std::to_string(line.bottom) + "), both finite");
  }

  FluidVariables<T, D>& fluid_;
  CellLinkedList<T, D>& cells_;
  WendlandC2Kernel<T, D> kernel_;
  std::vector<WaveGaugeLine<T, D>> lines_;
  T threshold_;
  Vec<T, D> up_{};
  std::vector<Index> first_, counts_;  // each gauge's samples in samples_
  std::vector<T> levels_;              // every sample's level, gauge after gauge
  std::vector<Vec<T, D>> points_;      // every sample's point, in the same order
  DiscreteVariable<Vec<T, D>> samples_;
  DiscreteVariable<T> sums_;
};

}  // namespace unisph::sph
