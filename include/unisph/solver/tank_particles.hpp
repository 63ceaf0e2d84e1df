#pragma once
// Particles of a closed rectangular tank case (host code, at set-up):
//  * the fluid: a lattice of spacing dx filling the column [0, column] from the corner;
//  * the wall: exactly four layers of dummy particles outside [0, tank], spacing dx across
//    the wall and the tank size divided into whole spacings along it (the tank need not be a
//    multiple of dx); each carries the unit normal towards the nearest point of the tank's
//    inside (the corners' normals point diagonally).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "unisph/core/error.hpp"
#include "unisph/core/vector.hpp"

namespace unisph::sph {

inline constexpr int wall_layers = 4;

// A body made with fill = "relaxed": its particles and the relaxation's final error (mean and
// max of |sum grad W V + G| h, shape/relaxed_particles.hpp).
struct RelaxedBodyReport {
  std::string name;
  std::size_t particles = 0;
  int iterations = 0;
  double mean_error = 0, max_error = 0;
};

template <class T, int D>
struct TankParticles {
  std::vector<Vec<T, D>> fluid;
  std::vector<Vec<T, D>> wall;
  std::vector<Vec<T, D>> wall_normal;
  // With obstacles (obstacle_particles.hpp): the wall particles each added after the tank's,
  // and the fluid lattice points removed because they overlapped one.
  std::vector<std::size_t> obstacle_wall_counts;
  std::size_t removed_fluid = 0;
  // The general form (body_particles.hpp): each fluid particle's initial velocity (empty: at
  // rest), and each named wall body's particle count in order (empty: the tank, then the obstacles).
  std::vector<Vec<T, D>> fluid_velocity;
  std::vector<std::pair<std::string, std::size_t>> wall_groups;
  // The general form's relaxed bodies (fill = "relaxed"), in the case's order.
  std::vector<RelaxedBodyReport> relaxed;
  // One rank's share of a case made in shares (several ranks): the whole case's fluid and wall
  // counts, and each particle's number in it (its id). Counts 0: the case is whole here.
  std::uint64_t fluid_whole = 0, wall_whole = 0;
  std::vector<std::uint64_t> fluid_numbers, wall_numbers;
};

namespace tank_detail {
inline std::vector<double> axis_coordinates(double length, double dx, bool with_wall) {
  const long n = std::max(1L, std::lround(length / dx));
  const double spacing = length / double(n);
  std::vector<double> x;
  if (with_wall)
    for (int k = wall_layers - 1; k >= 0; --k) x.push_back(-(k + 0.5) * dx);
  for (long i = 0; i < n; ++i) x.push_back((double(i) + 0.5) * spacing);
  if (with_wall)
    for (int k = 0; k < wall_layers; ++k) x.push_back(length + (k + 0.5) * dx);
  return x;
}
}  // namespace tank_detail

// The tank case's particles as a lattice with ids: particle k of the whole case (fluid: x
// fastest, then y, then z; walls: the same order over the wall lattice, skipping the inside)
// has id k, so that any box of it can be made alone with the ids the whole case gives (a run
// on several ranks makes only each rank's share: ids from closed-form counts, no pass over
// the rest).
template <int D>
class TankLattice {
 public:
  TankLattice(const std::vector<double>& tank, const std::vector<double>& column, double dx) : tank_(tank), dx_(dx) {
    for (int a = 0; a < 3; ++a) fluid_[a] = 1;
    for (int a = 0; a < D; ++a) fluid_[a] = std::lround(std::floor(column[a] / dx + 1e-9));
    for (int a = 0; a < D; ++a) wall_[a] = tank_detail::axis_coordinates(tank[a], dx, true);
    if (D == 2) wall_[2] = {0.0};
  }

  std::uint64_t fluid_count() const { return std::uint64_t(fluid_[0]) * std::uint64_t(fluid_[1]) * std::uint64_t(fluid_[2]); }
  std::uint64_t wall_count() const { return layers_before(wall_[2].size()); }
  // The fluid's lattice layers along its last axis (z in 3D, y in 2D): layer k holds the
  // particles at (k + 1/2) dx there.
  long fluid_layers() const { return fluid_[D - 1]; }
  double spacing() const { return dx_; }

  // f(id, position) for each fluid particle with lower <= position < upper, in id order.
  template <class F>
  void fluid_within(const double (&lower)[3], const double (&upper)[3], F&& f) const {
    std::vector<long> index[3];
    for (int a = 0; a < 3; ++a)
      for (long i = 0; i < fluid_[a]; ++i)
        if (a >= D || (fluid_at(i) >= lower[a] && fluid_at(i) < upper[a])) index[a].push_back(i);
    double p[3] = {0, 0, 0};
    for (long k : index[2])
      for (long j : index[1])
        for (long i : index[0]) {
          const long idx[3] = {i, j, k};
          for (int a = 0; a < D; ++a) p[a] = fluid_at(idx[a]);
          f(std::uint64_t(i) + std::uint64_t(fluid_[0]) * (std::uint64_t(j) + std::uint64_t(fluid_[1]) * std::uint64_t(k)), p);
        }
  }

  // f(id, position, normal) for each wall particle with lower <= position < upper, in id
  // order. The normal points towards the nearest point of the tank's inside (diagonally at
  // edges and corners).
  template <class F>
  void walls_within(const double (&lower)[3], const double (&upper)[3], F&& f) const {
    std::vector<std::size_t> index[3];
    for (int a = 0; a < 3; ++a)
      for (std::size_t i = 0; i < wall_[a].size(); ++i)
        if (a >= D || (wall_[a][i] >= lower[a] && wall_[a][i] < upper[a])) index[a].push_back(i);
    const std::size_t n0 = wall_[0].size();
    // A row inside the tank holds only its ends' wall layers: index[0] less its middle part.
    const auto middle_begin = std::lower_bound(index[0].begin(), index[0].end(), std::size_t(wall_layers));
    const auto middle_end = std::lower_bound(index[0].begin(), index[0].end(), n0 - wall_layers);
    for (std::size_t c : index[2])
      for (std::size_t b : index[1]) {
        const bool full_row = is_wall(2, c) || is_wall(1, b);
        const std::uint64_t row = layers_before(c) + rows_before(c, b);
        for (auto at = index[0].begin(); at != index[0].end(); ++at) {
          if (!full_row && at == middle_begin) at = middle_end;
          if (at == index[0].end()) break;
          const std::size_t a = *at;
          const std::uint64_t within = full_row || a < std::size_t(wall_layers) ? a : wall_layers + (a - (n0 - wall_layers));
          const double p[3] = {wall_[0][a], wall_[1][b], wall_[2][c]};
          double normal[3] = {0, 0, 0}, length = 0;
          for (int e = 0; e < D; ++e) {
            normal[e] = std::min(std::max(p[e], 0.0), tank_[e]) - p[e];
            length += normal[e] * normal[e];
          }
          length = std::sqrt(length);
          for (int e = 0; e < D; ++e) normal[e] /= length;
          f(row + within, p, normal);
        }
      }
  }

 private:
  double fluid_at(long i) const { return (double(i) + 0.5) * dx_; }
  bool is_wall(int axis, std::size_t i) const {
    const std::size_t n = wall_[axis].size();
    return axis < D && (i < std::size_t(wall_layers) || i >= n - wall_layers);
  }
  // The wall indices along `axis` below i.
  std::uint64_t walls_below(int axis, std::size_t i) const {
    if (axis >= D) return 0;
    const std::size_t n = wall_[axis].size(), L = wall_layers;
    return std::min(i, L) + (i > n - L ? i - (n - L) : 0);
  }
  // Wall particles in the z layers below c, and in layer c's rows below b.
  std::uint64_t layers_before(std::size_t c) const {
    const std::uint64_t n0 = wall_[0].size(), n1 = wall_[1].size(), ring = 2 * wall_layers;
    const std::uint64_t inner_layer = std::uint64_t(2 * wall_layers) * n0 + (n1 - 2 * wall_layers) * ring;
    const std::uint64_t full = walls_below(2, c);
    return full * n0 * n1 + (c - full) * inner_layer;
  }
  std::uint64_t rows_before(std::size_t c, std::size_t b) const {
    const std::uint64_t n0 = wall_[0].size(), ring = 2 * wall_layers;
    if (is_wall(2, c)) return b * n0;
    const std::uint64_t full = walls_below(1, b);
    return full * n0 + (b - full) * ring;
  }

  std::vector<double> tank_;
  double dx_;
  long fluid_[3];
  std::vector<double> wall_[3];
};

template <class T, int D>
TankParticles<T, D> make_tank_particles(const std::vector<double>& tank, const std::vector<double>& column, double dx) {
  TankParticles<T, D> out;
  const TankLattice<D> lattice(tank, column, dx);
  constexpr double inf = std::numeric_limits<double>::infinity();
  const double lower[3] = {-inf, -inf, -inf}, upper[3] = {inf, inf, inf};
  out.fluid.reserve(lattice.fluid_count());
  lattice.fluid_within(lower, upper, [&](std::uint64_t, const double* p) {
    Vec<T, D> x{};
    for (int a = 0; a < D; ++a) x[a] = T(p[a]);
    out.fluid.push_back(x);
  });
  out.wall.reserve(lattice.wall_count());
  out.wall_normal.reserve(lattice.wall_count());
  lattice.walls_within(lower, upper, [&](std::uint64_t, const double* p, const double* n) {
    Vec<T, D> x{}, normal{};
    for (int a = 0; a < D; ++a) x[a] = T(p[a]), normal[a] = T(n[a]);
    out.wall.push_back(x);
    out.wall_normal.push_back(normal);
  });
  return out;
}

}  // namespace unisph::sph
