#pragma once
// Body-fitted particles of a shape: the lattice points inside it (spacing dx, volume dx^D each),
// moved by the particle relaxation (relaxation/particle_relaxation.hpp) until the kernel sum of
// every particle, completed by the integral of the kernel over the outside of the shape, is
// uniform. Where a lattice fill steps along a curved or slanted surface, the relaxed particles
// line it at about dx / 2. The level set the relaxation runs against is built from the shape's
// own signed distance, at the finest spacing dx, so analytic primitives, booleans and meshes
// (through their level set) are all relaxed the same way.
//
//   shape::CompiledShape<2> water(difference(circle, walls));
//   std::vector<Vec2d> fluid = shape::relax_in_shape(par, water, dx, domain, 1000);
//   shape::LatticeParticles<2> wall = shape::make_relaxed_wall_particles(par, tank, dx, 4, domain, 1000);
//
// A wall is relaxed as its band: the solid within `layers` dx of its surface (the solid
// intersected with the shell of twice that thickness centred on its surface), so its inner face
// lies where the dummy particles must end and its outer face is the surface the fluid sees.
// Host code at set-up.
#include <array>
#include <cmath>
#include <type_traits>
#include <string>
#include <vector>

#include "unisph/core/box.hpp"
#include "unisph/exec/policy.hpp"
#include "unisph/levelset/multi_resolution_level_set.hpp"
#include "unisph/relaxation/particle_relaxation.hpp"
#include "unisph/shape/compiled_shape.hpp"
#include "unisph/shape/lattice_particles.hpp"
#include "unisph/shape/shape.hpp"

namespace unisph::shape {

// A compiled shape as the `shape` of a MultiResolutionLevelSet: nearest(p).squared_distance is
// the square of its signed distance, sign the sign of it. The booleans' distance (min / max of
// the operands') never exceeds the true distance, so the level set's band tagging, which asks
// whether the surface lies within a cell, errs on the side of more packages.
template <int D>
struct ShapeDistanceField {
  struct Nearest {
    Real squared_distance;
    Real signed_distance;
  };
  ShapeView<D> shape;
  UNISPH_HOST_DEVICE Nearest nearest(const Vec<Real, D>& p) const {
    const Real d = shape.signed_distance(p);
    return {d * d, d};
  }
  UNISPH_HOST_DEVICE int sign(const Vec<Real, D>&, const Nearest& n) const { return n.signed_distance > Real(0) ? 1 : -1; }
};

// A fluid relaxed in a periodic domain must fill it across its periodic faces with no surface
// within reach of a particle (relax_in_shape checks it): its shape's own faces on the periodic
// faces are no surface. This is the distance that check takes: the point folded into the domain
// along the periodic axes and kept `margin` inside their faces, so that those faces of the shape
// are never nearer than `margin` and any other surface is seen.
template <int D>
struct PeriodicShapeDistance {
  ShapeView<D> shape;
  Vec<Real, D> lower, upper;  // the domain
  Vec<Real, D> period;        // 0 along the other axes
  Real margin;
  Real operator()(const Vec<Real, D>& p) const {
    Vec<Real, D> q = p;
    for (int a = 0; a < D; ++a) {
      if (period[a] == Real(0)) continue;
      q[a] -= period[a] * std::floor((q[a] - lower[a]) / period[a]);
      const Real lo = lower[a] + margin, hi = upper[a] - margin;
      q[a] = lo > hi ? lower[a] + Real(0.5) * period[a] : (q[a] < lo ? lo : (q[a] > hi ? hi : q[a]));
    }
    return shape.signed_distance(q);
  }
};

// The side of a lattice point for the seeding: inside the shape (signed distance below zero).
template <int D>
struct InsideShape {
  ShapeView<D> shape;
  UNISPH_HOST_DEVICE bool operator()(const Vec<Real, D>& x) const { return shape.signed_distance(x) < Real(0); }
};

struct RelaxedFill {
  Index particles = 0;
  int iterations = 0;
  Real mean_error = 0, max_error = 0;  // |sum grad W V + G| h after the last move (particle_relaxation.hpp)
};

// The particles of `region` within `within`, seeded on the lattice x = (i + 1/2) dx (the lattice
// of fill_with_particles with origin 0) and relaxed for `iterations` (RelaxationSettings'
// schedule: FIRE, its quench, a final descent). Returns the positions in the relaxation's order.
// Along the axes a with periodic[a], `within` is a periodic domain that the region must fill
// (no surface within reach of a particle but the region's own faces on the periodic faces:
// PeriodicShapeDistance); the particles wrap through those faces, see their neighbours beyond
// them and relax against no surface (ParticleRelaxation::make_periodic); `within` must then be a
// whole number of dx long there, for the lattice to close on itself.
template <ExecutionPolicy P, int D>
std::vector<Vec<Real, D>> relax_in_shape(P policy, const Shape<D>& region, Real dx, const Box<Real, D>& within,
                                         int iterations, RelaxedFill* report = nullptr,
                                         const std::type_identity_t<std::array<bool, D>>& periodic = {}) {
  if (!(dx > Real(0)) || !std::isfinite(dx)) throw ShapeError("shape: the lattice spacing must be positive, got " + detail::text(dx));
  if (iterations < 0) throw ShapeError("shape: the relaxation needs a number of iterations >= 0, got " + std::to_string(iterations));
  CompiledShape<D> compiled(region);
  Box<Real, D> box = compiled.bounds();
  for (int k = 0; k < D; ++k) {
    // The region's box within `within`, snapped outwards to whole cells of the lattice.
    const Real lo = box.lower[k] > within.lower[k] ? box.lower[k] : within.lower[k];
    const Real hi = box.upper[k] < within.upper[k] ? box.upper[k] : within.upper[k];
    if (!std::isfinite(lo) || !std::isfinite(hi))
      throw ShapeError("shape: the relaxation's region is unbounded along axis " + std::to_string(k));
    if (!(hi > lo)) throw ShapeError("shape: the shape lies outside the region it is relaxed in");
    box.lower[k] = Real(std::floor(double(lo) / double(dx))) * dx;
    box.upper[k] = Real(std::ceil(double(hi) / double(dx))) * dx;
  }
  // The level set covers the box and every particle's kernel support beyond it.
  const Real pad = Real(2) * WendlandC2Kernel<Real, D>::smoothing_length_ratio * dx + dx;
  Vec<Real, D> lo = box.lower, hi = box.upper;
  for (int k = 0; k < D; ++k) lo[k] -= pad, hi[k] += pad;
  const ShapeView<D> view = compiled.view(policy);
  bool any_periodic = false;
  Vec<Real, D> period{};
  for (int a = 0; a < D; ++a)
    if (periodic[a]) {
      any_periodic = true;
      period[a] = within.upper[a] - within.lower[a];
      const double cells = double(period[a]) / double(dx);
      if (std::abs(cells - std::round(cells)) > 1e-6 * cells)
        throw ShapeError("shape: the periodic domain is " + detail::text(period[a]) + " long along axis " +
                         std::to_string(a) + ", not a whole number of the spacing " + detail::text(dx) +
                         ": the relaxed particles would not close on themselves across its faces");
    }
  MultiResolutionLevelSet<D> level_set(policy, ShapeDistanceField<D>{view}, lo, hi, dx);
  try {
    ParticleRelaxation<D> relaxation(policy, level_set, box, SeedRegion::inside, dx, InsideShape<D>{view});
    if (any_periodic) {
      // Periodic relaxation is built for a fluid that fills the domain: no surface within reach
      // (a kernel support and a spacing) of any seeded particle, the periodic faces aside.
      const PeriodicShapeDistance<D> distance{compiled.view(seq), within.lower, within.upper, period, Real(2) * pad};
      const std::vector<Vec<Real, D>> seeds = relaxation.positions().to_vector();
      for (const Vec<Real, D>& x : seeds)
        if (distance(x) > -pad) {
          std::string at;
          for (int a = 0; a < D; ++a) at += (a ? ", " : "") + detail::text(x[a]);
          throw ShapeError("shape: a relaxed fluid in a periodic domain must fill it with no surface within " +
                           detail::text(pad) + " of a particle, the periodic faces aside (a surface lies " +
                           detail::text(std::abs(distance(x))) + " from the lattice point (" + at +
                           ")); fill = \"lattice\" there");
        }
      relaxation.make_periodic(policy, within, periodic);
    }
    RelaxationSettings settings;
    settings.iterations = iterations;
    const std::vector<RelaxationRecord> history = relaxation.run(policy, settings);
    if (report) {
      report->particles = relaxation.size();
      report->iterations = iterations;
      report->mean_error = history.back().mean_error;
      report->max_error = history.back().max_error;
    }
    std::vector<Vec<Real, D>> points = relaxation.positions().to_vector();
    points.resize(relaxation.size());  // the owned particles (a periodic relaxation's images follow them)
    return points;
  } catch (const ShapeError&) {
    throw;
  } catch (const Error& e) {
    throw ShapeError(std::string("shape: ") + e.what());
  }
}

// The dummy particles of a wall, body-fitted: its band `layers` dx deep, within `within`,
// relaxed (relax_in_shape), each with the solid's unit normal out of it (central differences of
// the signed distance with a step of dx / 100, as make_wall_particles).
template <ExecutionPolicy P, int D>
LatticeParticles<D> make_relaxed_wall_particles(P policy, const Shape<D>& solid, Real dx, int layers,
                                                const Box<Real, D>& within, int iterations, RelaxedFill* report = nullptr) {
  if (layers < 1) throw ShapeError("shape: a wall needs at least one layer, got " + std::to_string(layers));
  const Shape<D> band = intersection_of<D>(solid, shell<D>(solid, Real(2 * layers) * dx));
  LatticeParticles<D> out;
  out.position = relax_in_shape(policy, band, dx, within, iterations, report);
  CompiledShape<D> compiled(solid);
  const ShapeView<D> host = compiled.view(seq);
  out.normal.reserve(out.position.size());
  for (const Vec<Real, D>& x : out.position) out.normal.push_back(host.normal(x, dx / Real(100)));
  return out;
}

}  // namespace unisph::shape
