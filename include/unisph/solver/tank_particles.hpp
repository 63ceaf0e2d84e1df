#pragma once
// Particles of a closed rectangular tank case (host code, at set-up):
//  * the fluid: a lattice of spacing dx filling the column [0, column] from the corner;
//  * the wall: exactly four layers of dummy particles outside [0, tank], spacing dx across
//    the wall and the tank size divided into whole spacings along it (the tank need not be a
//    multiple of dx); each carries the unit normal towards the nearest point of the tank's
//    inside (the corners' normals point diagonally).
#include <cmath>
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

template <class T, int D>
TankParticles<T, D> make_tank_particles(const std::vector<double>& tank, const std::vector<double>& column, double dx) {
  TankParticles<T, D> out;
  // Fluid: whole particles only, at (i + 1/2) dx.
  long count[3] = {1, 1, 1};
  for (int a = 0; a < D; ++a) count[a] = std::lround(std::floor(column[a] / dx + 1e-9));
  for (long k = 0; k < count[2]; ++k)
    for (long j = 0; j < count[1]; ++j)
      for (long i = 0; i < count[0]; ++i) {
        Vec<T, D> x{};
        const long idx[3] = {i, j, k};
        for (int a = 0; a < D; ++a) x[a] = T((double(idx[a]) + 0.5) * dx);
        out.fluid.push_back(x);
      }
  std::vector<double> coords[3];
  for (int a = 0; a < D; ++a) coords[a] = tank_detail::axis_coordinates(tank[a], dx, true);
  if (D == 2) coords[2] = {0.0};
  for (double z : coords[2])
    for (double y : coords[1])
      for (double x : coords[0]) {
        const double p[3] = {x, y, z};
        double inside[3] = {0, 0, 0};
        bool outside = false;
        for (int a = 0; a < D; ++a) {
          inside[a] = std::min(std::max(p[a], 0.0), tank[a]);
          outside = outside || inside[a] != p[a];
        }
        if (!outside) continue;
        Vec<T, D> position{}, normal{};
        double length = 0;
        for (int a = 0; a < D; ++a) length += (inside[a] - p[a]) * (inside[a] - p[a]);
        length = std::sqrt(length);
        for (int a = 0; a < D; ++a) {
          position[a] = T(p[a]);
          normal[a] = T((inside[a] - p[a]) / length);
        }
        out.wall.push_back(position);
        out.wall_normal.push_back(normal);
      }
  return out;
}

}  // namespace unisph::sph
