#pragma once
// Obstacles: static bodies of a case loaded from the particle files `unisph generate` writes
// (body-fitted particles relaxed against a level set; io/vtk_xml_reader.hpp reads them). Host
// code, at set-up.
//
// The solver's walls are dummy particles of volume dx^D in exactly `wall_layers` layers, each
// with the unit normal pointing into the fluid. An obstacle gives the same: of the file's
// particles (phi < 0 inside the body) those with phi >= -wall_layers dx, with the level set's
// normal (out of the body, so into the fluid). They join the tank's wall body: the kernels treat
// every wall particle alike (normal, volume, hydrostatic dummy pressure), so one contact relation
// serves both and nothing in the kernels changes.
//
// The fluid lattice must not overlap a body: a lattice point is removed when the body's signed
// distance there, estimated from the nearest body particle w (all of the file's particles, so
// that a point deep inside is caught too) as phi_w + n_w . (x - x_w), is below dx / 2 (the
// distance a lattice particle keeps from the tank's wall).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "unisph/core/vector.hpp"
#include "unisph/io/vtk_xml_reader.hpp"
#include "unisph/solver/case_description.hpp"
#include "unisph/solver/case_file.hpp"
#include "unisph/solver/tank_particles.hpp"

namespace unisph::sph {

template <int D>
struct ObstacleParticles {
  std::vector<Vec<double, D>> position;  // every particle of the file, translated
  std::vector<Vec<double, D>> normal;    // the file's normals (unit where kept as wall)
  std::vector<double> phi;               // signed distance to the surface, negative inside
  std::vector<std::size_t> wall;         // the particles within wall_layers dx of the surface
};

namespace obstacle_detail {

inline std::string text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
template <int D>
std::string text(const Vec<double, D>& v) {
  std::string s = "(";
  for (int a = 0; a < D; ++a) s += (a ? ", " : "") + text(v[a]);
  return s + ")";
}

}  // namespace obstacle_detail

// Reads and checks obstacle k of the case for the case's dx and dimension. Every problem is a
// CaseFileError of one line: "case.toml:LINE: key 'obstacle.file': FILE: what is wrong".
template <int D>
ObstacleParticles<D> load_obstacle(const CaseDescription& c, std::size_t k) {
  using obstacle_detail::text;
  const ObstacleDescription& o = c.obstacles.at(k);
  const std::string where = c.source + ":" + std::to_string(o.line) + ": key 'obstacle.file': ";
  const auto fail = [&](const std::string& what) { throw CaseFileError(where + o.file + ": " + what); };
  io::PolyDataFile file;
  try {
    file = io::read_vtp(o.file);
  } catch (const io::VtkReadError& e) {
    throw CaseFileError(where + e.what());
  }
  try {
    const auto has_field = [&](const std::string& name) {
      for (const io::VtkArray& a : file.field_arrays)
        if (a.name == name) return true;
      return false;
    };
    for (const char* name : {"Spacing", "Dimension", "Inside"})
      if (!has_field(name))
        fail(std::string("has no field array '") + name + "' (not a particle file of `unisph generate`)");
    const double dimension = file.field_value("Dimension");
    if (dimension != D) fail("is a " + text(dimension) + "D particle set; the case is " + std::to_string(D) + "D");
    if (file.field_value("Inside") != 1)
      fail("holds particles around a body (generated with --outside); an obstacle needs the body's own particles");
    const double spacing = file.field_value("Spacing");
    if (!(std::abs(spacing - c.dx) <= 1e-9 * c.dx))
      fail("was generated with dx = " + text(spacing) + "; the case's dx is " + text(c.dx) +
           " (generate it again with --dx " + text(c.dx) + ")");
    if (file.points == 0) fail("holds no particles");
    const io::VtkArray& volume = file.point_array("Volume", 1);
    const io::VtkArray& phi = file.point_array("NormalDistance", 1);
    const io::VtkArray& normal = file.point_array("Normal", 3);
    const double wall_volume = std::pow(c.dx, D);
    ObstacleParticles<D> out;
    for (std::uint64_t i = 0; i < file.points; ++i) {
      Vec<double, D> x{}, n{};
      for (int a = 0; a < D; ++a) {
        x[a] = file.coordinates[3 * i + a] + (o.translation.empty() ? 0.0 : o.translation[a]);
        n[a] = normal.values[3 * i + a];
      }
      if (D == 2 && (file.coordinates[3 * i + 2] != 0 || normal.values[3 * i + 2] != 0))
        fail("particle " + std::to_string(i) + " has a non-zero z (point or Normal); a 2D particle set has z = 0");
      // The kernels give every wall particle the volume dx^D; a relaxed set has exactly that.
      if (!(std::abs(volume.values[i] - wall_volume) <= 1e-5 * wall_volume))
        fail("particle " + std::to_string(i) + " has Volume " + text(volume.values[i]) + "; a wall particle has dx^" +
             std::to_string(D) + " = " + text(wall_volume));
      for (int a = 0; a < D; ++a)
        if (!(x[a] > 0 && x[a] < c.tank[a])) {
          std::string tank = "[0, " + text(c.tank[0]) + "]";
          for (int b = 1; b < D; ++b) tank += " x [0, " + text(c.tank[b]) + "]";
          std::string translation;
          for (int b = 0; b < D && !o.translation.empty(); ++b) translation += (b ? ", " : " (translated by [") + text(o.translation[b]);
          fail("particle " + std::to_string(i) + " at " + text(x) + (translation.empty() ? "" : translation + "])") +
               " lies outside the tank " + tank + "; an obstacle must lie inside it");
        }
      if (phi.values[i] >= -wall_layers * c.dx) {
        const double length = norm(n);
        if (!(std::abs(length - 1) < 0.5))
          fail("particle " + std::to_string(i) + " (NormalDistance " + text(phi.values[i]) + ") has a Normal of length " +
               text(length) + "; a wall particle needs a unit normal");
        n = n / length;
        out.wall.push_back(out.position.size());
      }
      out.position.push_back(x);
      out.normal.push_back(n);
      out.phi.push_back(phi.values[i]);
    }
    if (out.wall.empty()) fail("has no particle within " + std::to_string(wall_layers) + " dx of its surface");
    return out;
  } catch (const io::VtkReadError& e) {
    throw CaseFileError(where + e.what());
  }
}

// The nearest body particle to a point, on a uniform grid of cells 2 dx wide over the body.
template <int D>
class NearestBodyParticle {
 public:
  NearestBodyParticle(const std::vector<Vec<double, D>>& position, double dx)
      : position_(position), cell_(2 * dx), count_{} {
    lower_ = position.front();
    Vec<double, D> upper = lower_;
    for (const Vec<double, D>& x : position)
      for (int a = 0; a < D; ++a) lower_[a] = std::min(lower_[a], x[a]), upper[a] = std::max(upper[a], x[a]);
    std::size_t cells = 1;
    for (int a = 0; a < D; ++a) {
      count_[a] = long(std::floor((upper[a] - lower_[a]) / cell_)) + 1;
      cells *= std::size_t(count_[a]);
    }
    start_.assign(cells + 1, 0);
    for (const Vec<double, D>& x : position) ++start_[cell_of(x) + 1];
    for (std::size_t k = 0; k < cells; ++k) start_[k + 1] += start_[k];
    order_.resize(position.size());
    std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < position.size(); ++i) order_[fill[cell_of(position[i])]++] = i;
  }

  // The nearest particle within 2 dx of x, or size() when there is none.
  std::size_t find(const Vec<double, D>& x) const {
    long centre[D];
    for (int a = 0; a < D; ++a) centre[a] = long(std::floor((x[a] - lower_[a]) / cell_));
    std::size_t best = position_.size();
    double best_distance = cell_ * cell_;
    long offset[D] = {};
    for (int a = 0; a < D; ++a) offset[a] = -1;
    for (;;) {
      std::size_t cell = 0;
      bool inside = true;
      for (int a = D - 1; a >= 0; --a) {
        const long c = centre[a] + offset[a];
        inside = inside && c >= 0 && c < count_[a];
        cell = cell * std::size_t(count_[a]) + std::size_t(std::max(c, 0L));
      }
      if (inside)
        for (std::size_t k = start_[cell]; k < start_[cell + 1]; ++k) {
          const Vec<double, D> r = x - position_[order_[k]];
          const double distance = dot(r, r);
          if (distance < best_distance) best_distance = distance, best = order_[k];
        }
      int a = 0;
      while (a < D && offset[a] == 1) offset[a++] = -1;
      if (a == D) break;
      ++offset[a];
    }
    return best;
  }

 private:
  std::size_t cell_of(const Vec<double, D>& x) const {
    std::size_t cell = 0;
    for (int a = D - 1; a >= 0; --a)
      cell = cell * std::size_t(count_[a]) +
             std::size_t(std::clamp(long(std::floor((x[a] - lower_[a]) / cell_)), 0L, count_[a] - 1));
    return cell;
  }

  const std::vector<Vec<double, D>>& position_;
  double cell_;
  long count_[D];
  Vec<double, D> lower_;
  std::vector<std::size_t> start_, order_;
};

// The body's signed distance at x estimated from its nearest particle (+infinity where no body
// particle lies within 2 dx: the body is filled at spacing dx, so x is then outside it).
template <int D>
double obstacle_distance(const ObstacleParticles<D>& body, const NearestBodyParticle<D>& nearest, const Vec<double, D>& x) {
  const std::size_t w = nearest.find(x);
  if (w == body.position.size()) return std::numeric_limits<double>::infinity();
  const Vec<double, D> r = x - body.position[w];
  const double length = norm(body.normal[w]);
  // Deep inside, where the level set may give no normal, the distance bound suffices.
  return body.phi[w] + (std::abs(length - 1) < 0.5 ? dot(body.normal[w], r) / length : norm(r));
}

// Adds the case's obstacles to its tank particles: their wall layers join the wall, and the
// fluid lattice points within dx / 2 of a body (or inside it) are removed.
template <class T, int D>
void add_obstacles(TankParticles<T, D>& particles, const CaseDescription& c) {
  for (std::size_t k = 0; k < c.obstacles.size(); ++k) {
    const ObstacleParticles<D> body = load_obstacle<D>(c, k);
    const NearestBodyParticle<D> nearest(body.position, c.dx);
    std::vector<Vec<T, D>> kept, kept_velocity;
    for (std::size_t i = 0; i < particles.fluid.size(); ++i) {
      const Vec<T, D>& x = particles.fluid[i];
      Vec<double, D> p{};
      for (int a = 0; a < D; ++a) p[a] = double(x[a]);
      if (obstacle_distance(body, nearest, p) >= 0.5 * c.dx) {
        kept.push_back(x);
        if (!particles.fluid_velocity.empty()) kept_velocity.push_back(particles.fluid_velocity[i]);
      }
    }
    particles.removed_fluid += particles.fluid.size() - kept.size();
    particles.fluid = std::move(kept);
    if (!particles.fluid_velocity.empty()) particles.fluid_velocity = std::move(kept_velocity);
    for (std::size_t w : body.wall) {
      Vec<T, D> x{}, n{};
      for (int a = 0; a < D; ++a) x[a] = T(body.position[w][a]), n[a] = T(body.normal[w][a]);
      particles.wall.push_back(x);
      particles.wall_normal.push_back(n);
    }
    particles.obstacle_wall_counts.push_back(body.wall.size());
    if (!particles.wall_groups.empty())
      particles.wall_groups.emplace_back("obstacle_" + std::to_string(k + 1), body.wall.size());
  }
}

}  // namespace unisph::sph
