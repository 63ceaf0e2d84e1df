#pragma once
// Particles of a general-form case (case_description.hpp: [[shape]], [[body]], [domain]), host
// code at set-up, the shapes evaluated in kernels on the run's policy:
//
//  * each wall body: the dummy particles of its shape's solid side on the lattice
//    x = (i + 1/2) dx, `layers` deep, with the unit normal out of the solid (into the fluid);
//  * each fluid body: its shape filled on the same lattice (whole cells, shape/lattice_particles.hpp),
//    less the points within dx / 2 of any wall body's surface (counted), with its initial velocity;
//  * the [[obstacle]] particle files, as in the short form, after the wall bodies;
//  * with fill = "relaxed" a body's particles are body-fitted instead (shape/relaxed_particles.hpp):
//    a wall's band `layers` dx deep, a fluid's shape less the walls', each relaxed within the domain.
//
// Shapes are built once per name and shared by every body and boolean that names them; the
// level set of a geometry file is built once per file (shape::MeshLevelSetCache). Every
// problem is a CaseFileError of one line naming the case file, the line and the key.
#include <array>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "unisph/exec/policy.hpp"
#include "unisph/shape/compiled_shape.hpp"
#include "unisph/shape/lattice_particles.hpp"
#include "unisph/shape/mesh_level_set.hpp"
#include "unisph/shape/relaxed_particles.hpp"
#include "unisph/shape/shape.hpp"
#include "unisph/solver/case_description.hpp"
#include "unisph/solver/case_file.hpp"
#include "unisph/solver/tank_particles.hpp"

namespace unisph::sph {

template <int D>
class ShapeBuilder {
 public:
  explicit ShapeBuilder(const CaseDescription& c) : case_(c) {}

  // The shape named `name`, built (with its operands) on first request.
  template <ExecutionPolicy P>
  const shape::Shape<D>& get(P policy, const std::string& name) {
    if (auto found = built_.find(name); found != built_.end()) return found->second;
    const ShapeDescription* d = nullptr;
    for (const ShapeDescription& s : case_.shapes)
      if (s.name == name) d = &s;
    if (!d) throw CaseFileError(case_.source + ": key 'shape': no shape is named '" + name + "'");
    try {
      shape::Shape<D> s = primitive(policy, *d);
      s = transformed(*d, s);
      return built_.emplace(name, s).first->second;
    } catch (const shape::ShapeError& e) {
      throw CaseFileError(case_.source + ":" + std::to_string(d->line) + ": key 'shape' ('" + d->name + "'): " + e.what());
    } catch (const CaseFileError&) {
      throw;
    } catch (const Error& e) {  // a geometry file that cannot be read or used
      throw CaseFileError(case_.source + ":" + std::to_string(d->line) + ": key 'shape.file' ('" + d->name + "'): " + e.what());
    }
  }

 private:
  using V = Vec<Real, D>;
  static V vec(const std::vector<double>& v) {
    V x{};
    for (int a = 0; a < D; ++a) x[a] = Real(v[std::size_t(a)]);
    return x;
  }
  static const std::vector<double>& need(const ShapeDescription& d, const char* key) {
    const std::vector<double>* v = d.value(key);
    if (!v) throw shape::ShapeError(std::string("shape: missing value '") + key + "'");
    return *v;
  }

  template <ExecutionPolicy P>
  shape::Shape<D> primitive(P policy, const ShapeDescription& d) {
    const std::string& t = d.type;
    if (t == "box") return shape::box<D>(vec(need(d, "lower")), vec(need(d, "upper")));
    if (t == "sphere") return shape::sphere<D>(vec(need(d, "center")), Real(need(d, "radius")[0]));
    if (t == "half_space") return shape::half_space<D>(vec(need(d, "point")), vec(need(d, "normal")));
    if constexpr (D == 3) {
      if (t == "cylinder")
        return shape::cylinder(vec(need(d, "start")), vec(need(d, "end")), Real(need(d, "radius")[0]));
      if (t == "mesh") return shape::triangle_mesh(policy, cache_, d.file, Real(case_.dx));
    } else {
      if (t == "polygon") return shape::polygon(policy, cache_, d.file, Real(case_.dx));
    }
    std::vector<shape::Shape<D>> operands;
    for (const std::string& o : d.operands) operands.push_back(get(policy, o));
    if (t == "union") return shape::union_of<D>(operands);
    if (t == "intersection") return shape::intersection_of<D>(operands);
    if (t == "difference") {
      std::vector<shape::Shape<D>> rest(operands.begin() + 1, operands.end());
      return shape::difference<D>(operands[0], rest.size() == 1 ? rest[0] : shape::union_of<D>(rest));
    }
    if (t == "shell") return shape::shell<D>(operands.at(0), Real(need(d, "thickness")[0]));
    throw shape::ShapeError("shape: unknown type '" + t + "' in " + std::to_string(D) + "D");
  }

  // scale (about the origin), rotation (degrees, about `pivot`), translation, in that order.
  shape::Shape<D> transformed(const ShapeDescription& d, shape::Shape<D> s) const {
    if (const auto* f = d.value("scale")) s = shape::scale<D>(s, Real((*f)[0]));
    if (const auto* r = d.value("rotation")) {
      const Real angle = Real((*r)[0] * std::numbers::pi / 180.0);
      const V pivot = d.value("pivot") ? vec(*d.value("pivot")) : V{};
      if constexpr (D == 3)
        s = shape::rotate(s, angle, vec(*d.value("axis")), pivot);
      else
        s = shape::rotate(s, angle, pivot);
    }
    if (const auto* t = d.value("translation")) s = shape::translate<D>(s, vec(*t));
    return s;
  }

  const CaseDescription& case_;
  shape::MeshLevelSetCache<D> cache_;
  std::map<std::string, shape::Shape<D>> built_;
};

// A wall particle's normal from its shape points out of the nearest surface of the solid. For
// the deep layers of a wall whose dry face is near (a tank made as the difference of two boxes,
// its outer box no larger than the domain) that is the dry face. The fluid must see normals out
// of the wetted face, so each normal is checked against the space the fluid can reach (inside
// the domain, outside every wall): kept where that space lies along +n within the wall's depth;
// reversed where it lies along -n only; otherwise (the deep corner of such a tank) replaced by
// the direction to the nearest lattice point of that space, an approximation (docs/user_guide.md:
// let the tank's outer box reach beyond the domain, and every normal a fluid particle sees is the
// shape's own). Host code (seq), once at set-up; returns how many normals were changed.
template <class T, int D>
Index orient_towards_fluid_space(const std::vector<Vec<T, D>>& wall, std::vector<Vec<T, D>>& normal,
                                 shape::CompiledShape<D>& all_walls, const Box<Real, D>& domain, Real dx,
                                 const std::vector<BodyDescription>& bodies) {
  int deepest = 1;
  for (const BodyDescription& b : bodies) deepest = std::max(deepest, b.layers);
  const shape::ShapeView<D> solid = all_walls.view(seq);
  const auto reachable = [&](const Vec<Real, D>& q) { return domain.contains(q) && solid.signed_distance(q) > Real(0); };
  const auto reaches = [&](const Vec<Real, D>& x, const Vec<Real, D>& n) {
    for (int step = 1; step <= deepest + 1; ++step) {
      Vec<Real, D> q;
      for (int a = 0; a < D; ++a) q[a] = x[a] + Real(step) * dx * n[a];
      if (!domain.contains(q)) return false;
      if (solid.signed_distance(q) > Real(0)) return true;
    }
    return false;
  };
  Index changed = 0;
  for (std::size_t k = 0; k < wall.size(); ++k) {
    Vec<Real, D> x, n;
    for (int a = 0; a < D; ++a) x[a] = Real(wall[k][a]), n[a] = Real(normal[k][a]);
    if (reaches(x, n)) continue;
    ++changed;
    if (reaches(x, -n)) {
      normal[k] = -normal[k];
      continue;
    }
    // The nearest reachable lattice point within the depth (+ 1) in every direction.
    const int r = deepest + 1;
    Real best = std::numeric_limits<Real>::max();
    Vec<Real, D> towards{};
    long long offset[3] = {0, 0, 0};
    const long long side = 2 * r + 1;
    long long total = 1;
    for (int a = 0; a < D; ++a) total *= side;
    for (long long m = 0; m < total; ++m) {
      long long rest = m;
      Vec<Real, D> q, d;
      Real squared = 0;
      for (int a = 0; a < D; ++a) {
        offset[a] = rest % side - r;
        rest /= side;
        d[a] = Real(offset[a]) * dx;
        q[a] = x[a] + d[a];
        squared += d[a] * d[a];
      }
      if (squared > Real(0) && squared < best && reachable(q)) best = squared, towards = d;
    }
    if (best < std::numeric_limits<Real>::max()) {
      const Real length = std::sqrt(best);
      for (int a = 0; a < D; ++a) normal[k][a] = T(towards[a] / length);
    }
  }
  return changed;
}

// A fluid body with fill = "relaxed": its shape less every wall's (so the relaxed particles line
// the walls' surfaces instead of being removed next to them), within the domain, relaxed.
template <class T, int D, ExecutionPolicy P>
void append_relaxed_fluid(P policy, const CaseDescription& c, const BodyDescription& b, const shape::Shape<D>& fluid,
                          const std::vector<shape::Shape<D>>& walls, const Box<Real, D>& domain, TankParticles<T, D>& out) {
  const std::string where = c.source + ":" + std::to_string(b.line) + ": key 'body.shape' (body '" + b.name + "'): ";
  {
    const shape::CompiledShape<D> compiled(fluid);
    if (compiled.bounded()) {
      const Box<Real, D>& bounds = compiled.bounds();
      for (int a = 0; a < D; ++a)
        if (bounds.lower[a] < domain.lower[a] || bounds.upper[a] > domain.upper[a])
          throw CaseFileError(where + "the fluid's shape '" + b.shape + "' reaches outside the domain");
    }
  }
  const shape::Shape<D> region = walls.empty() ? fluid : shape::difference<D>(fluid, shape::union_of<D>(walls));
  std::vector<Vec<Real, D>> points;
  shape::RelaxedFill fill;
  try {
    // Along periodic axes the fluid continues across the domain's faces (a periodic box or channel).
    std::array<bool, D> periodic{};
    for (int a = 0; a < D; ++a) periodic[a] = c.domain.is_periodic(a);
    points = shape::relax_in_shape(policy, region, Real(c.dx), domain, b.relaxation_iterations, &fill, periodic);
  } catch (const shape::ShapeError& e) {
    throw CaseFileError(where + e.what());
  }
  out.relaxed.push_back({b.name, points.size(), fill.iterations, double(fill.mean_error), double(fill.max_error)});
  Vec<T, D> velocity{};
  for (int a = 0; a < D; ++a) velocity[a] = T(b.velocity.empty() ? 0.0 : b.velocity[std::size_t(a)]);
  for (const Vec<Real, D>& x : points) {
    Vec<T, D> y{};
    for (int a = 0; a < D; ++a) y[a] = T(x[a]);
    out.fluid.push_back(y);
    out.fluid_velocity.push_back(velocity);
  }
}

// The particles of the general form's bodies, made on `policy` (the same points on every one):
// fluid (with fluid_velocity), wall and wall_normal with one wall_groups entry per wall body,
// removed_fluid the lattice points within dx / 2 of a wall.
template <class T, int D, ExecutionPolicy P>
TankParticles<T, D> make_body_particles(P policy, const CaseDescription& c) {
  using V = Vec<Real, D>;
  ShapeBuilder<D> shapes(c);
  TankParticles<T, D> out;
  Box<Real, D> domain{};
  for (int a = 0; a < D; ++a) {
    domain.lower[a] = Real(c.domain.lower[std::size_t(a)]);
    domain.upper[a] = Real(c.domain.upper[std::size_t(a)]);
  }
  const Real dx = Real(c.dx);
  shape::LatticeOptions<D> options;
  options.region = domain;  // unbounded shapes (a half-space) are filled within the domain
  const auto where = [&](const BodyDescription& b, const std::string& key) {
    return c.source + ":" + std::to_string(b.line) + ": key '" + key + "' (body '" + b.name + "'): ";
  };
  const auto outside = [&](const std::vector<V>& points) {
    for (const V& x : points)
      if (!domain.contains(x)) return true;
    return false;
  };

  std::vector<shape::Shape<D>> walls;
  for (const BodyDescription& b : c.bodies) {
    if (b.kind != "wall") continue;
    const shape::Shape<D>& s = shapes.get(policy, b.shape);
    walls.push_back(s);
    shape::CompiledShape<D> compiled(s);
    shape::LatticeParticles<D> p;
    try {
      if (b.fill == "relaxed") {
        shape::RelaxedFill fill;
        p = shape::make_relaxed_wall_particles(policy, s, dx, b.layers, domain, b.relaxation_iterations, &fill);
        out.relaxed.push_back({b.name, p.position.size(), fill.iterations, double(fill.mean_error), double(fill.max_error)});
      } else {
        p = shape::make_wall_particles(policy, compiled, dx, b.layers, options);
      }
    } catch (const shape::ShapeError& e) {
      throw CaseFileError(where(b, "body.shape") + e.what());
    }
    if (p.position.empty())
      throw CaseFileError(where(b, "body.shape") + "the wall has no particle within the domain at dx = " + std::to_string(c.dx) +
                          " (shape '" + b.shape + "' lies outside the domain or is thinner than the lattice)");
    for (std::size_t k = 0; k < p.position.size(); ++k) {
      Vec<T, D> x{}, n{};
      for (int a = 0; a < D; ++a) {
        x[a] = T(p.position[k][a]);
        n[a] = T(p.normal[k][a]);
      }
      out.wall.push_back(x);
      out.wall_normal.push_back(n);
    }
    out.wall_groups.emplace_back(b.name, p.position.size());
  }
  std::unique_ptr<shape::CompiledShape<D>> all_walls;
  if (!walls.empty()) all_walls = std::make_unique<shape::CompiledShape<D>>(shape::union_of<D>(walls));
  if (all_walls) orient_towards_fluid_space<T, D>(out.wall, out.wall_normal, *all_walls, domain, dx, c.bodies);

  for (const BodyDescription& b : c.bodies) {
    if (b.kind != "fluid") continue;
    if (b.fill == "relaxed") {
      append_relaxed_fluid<T, D>(policy, c, b, shapes.get(policy, b.shape), walls, domain, out);
      continue;
    }
    shape::CompiledShape<D> compiled(shapes.get(policy, b.shape));
    // A bounded fluid shape is filled whole (and refused if it reaches out of the domain); an
    // unbounded one (a half-space, or a boolean with one) within the domain.
    const shape::LatticeOptions<D> fill_options = compiled.bounded() ? shape::LatticeOptions<D>{} : options;
    std::vector<V> points = shape::fill_with_particles(policy, compiled, dx, shape::FillRule::whole_cell, fill_options);
    if (points.empty())
      throw CaseFileError(where(b, "body.shape") + "the fluid fills to no particle at dx = " + std::to_string(c.dx) +
                          " (shape '" + b.shape + "' is outside the domain or thinner than dx)");
    // A bounded shape that reaches out of the domain is a mistake: its particles would leave at once.
    if (compiled.bounded() && outside(points))
      throw CaseFileError(where(b, "body.shape") + "the fluid's shape '" + b.shape + "' reaches outside the domain");
    const Index made = points.size();
    if (all_walls) out.removed_fluid += shape::remove_near_wall(policy, points, *all_walls, dx);
    if (points.empty())
      throw CaseFileError(where(b, "body.shape") + "every one of the fluid's " + std::to_string(made) +
                          " lattice points lies within dx / 2 of a wall");
    Vec<T, D> velocity{};
    for (int a = 0; a < D; ++a) velocity[a] = T(b.velocity.empty() ? 0.0 : b.velocity[std::size_t(a)]);
    for (const V& x : points) {
      Vec<T, D> y{};
      for (int a = 0; a < D; ++a) y[a] = T(x[a]);
      out.fluid.push_back(y);
      out.fluid_velocity.push_back(velocity);
    }
  }
  return out;
}

}  // namespace unisph::sph
