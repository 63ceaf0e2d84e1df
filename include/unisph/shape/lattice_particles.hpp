#pragma once
// Particles from shapes on a lattice of spacing dx, the lattice points x = origin + (i + 1/2) dx
// (integer i of any sign; origin 0 by default, so every body of a case shares one lattice and
// a box [0, L] filled this way gives make_tank_particles' fluid bit for bit):
//
//   fill_with_particles(policy, fluid, dx)        the points whose cell lies in the shape
//   make_wall_particles(policy, solid, dx, 4)     the dummy wall particles of a solid, normals out of it
//   remove_near_wall(policy, fluid_points, solid, dx)   fluid points within dx / 2 of a wall
//
// Each evaluates the shape at every lattice point of the shape's bounding box (or of a given
// region, needed for unbounded shapes) in a kernel on the policy, then compacts the chosen points
// in lattice order (x fastest, then y, then z): the same points in the same order on every policy.

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "unisph/core/box.hpp"
#include "unisph/core/uncontracted_arithmetic.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/reduce_ops.hpp"
#include "unisph/memory/discrete_variable.hpp"
#include "unisph/shape/compiled_shape.hpp"

namespace unisph::shape {

inline constexpr int default_wall_layers = 4;
// Round-off allowance of the lattice tests against dx/2, relative to dx: lattice points exactly
// dx/2 from a surface (a box on the lattice's cell faces) must fall on the intended side.
inline constexpr Real lattice_tolerance = sizeof(Real) == 4 ? Real(1e-3) : Real(1e-9);

// Which lattice points a fill takes.
enum class FillRule {
  // The point's cell [x - dx/2, x + dx/2]^D lies in the shape (signed distance <= -dx/2, within
  // lattice_tolerance): whole particles only, today's tank convention; exact for boxes, for
  // curved shapes the points at least dx/2 deep.
  whole_cell,
  // The point itself lies in the shape (signed distance < 0).
  centre_inside,
};

// Where a lattice lies and which part of it is searched.
template <int D>
struct LatticeOptions {
  Vec<Real, D> origin{};                  // lattice points at origin + (i + 1/2) dx
  std::optional<Box<Real, D>> region;     // searched region, intersected with the shape's bounds
};

// The lattice points of a box of indices, numbered x fastest.
template <int D>
struct LatticeBlock {
  Vec<Real, D> origin;
  Real spacing;
  long long first[D];
  long long count[D];

  UNISPH_HOST_DEVICE Index size() const {
    Index n = 1;
    for (int k = 0; k < D; ++k) n *= Index(count[k]);
    return n;
  }
  // Unfused products and sums: the same bits on every policy.
  UNISPH_HOST_DEVICE Vec<Real, D> point(Index n) const {
    Vec<Real, D> x;
    for (int k = 0; k < D; ++k) {
      const long long i = first[k] + (long long)(n % Index(count[k]));
      n /= Index(count[k]);
      x[k] = uncontracted::add(origin[k], uncontracted::mul(Real(i) + Real(0.5), spacing));
    }
    return x;
  }
};

// Marks the lattice points where below < signed distance < above.
template <int D>
struct MarkLatticePoints {
  ShapeView<D> shape;
  LatticeBlock<D> lattice;
  Real below, above;
  View<std::uint32_t> marked;
  UNISPH_HOST_DEVICE void operator()(Index n) const {
    const Real d = shape.signed_distance(lattice.point(n));
    marked[n] = d > below && d < above ? 1u : 0u;
  }
};

struct CountMarked {
  View<const std::uint32_t> marked;
  UNISPH_HOST_DEVICE Index operator()(Index n) const { return marked[n]; }
};

// Writes the marked points (and, with a step, the shape's outward normal there) to their slots.
template <int D>
struct GatherLatticePoints {
  ShapeView<D> shape;
  LatticeBlock<D> lattice;
  Real normal_step;  // 0: no normals
  View<const std::uint32_t> marked, slot;
  View<Vec<Real, D>> position, normal;
  UNISPH_HOST_DEVICE void operator()(Index n) const {
    if (!marked[n]) return;
    const Vec<Real, D> x = lattice.point(n);
    position[slot[n]] = x;
    if (normal_step > Real(0)) normal[slot[n]] = shape.normal(x, normal_step);
  }
};

// Marks the points to keep: signed distance of the wall at least `clearance`.
template <int D>
struct MarkClearOfWall {
  ShapeView<D> wall;
  View<const Vec<Real, D>> points;
  Real clearance;
  View<std::uint32_t> keep;
  UNISPH_HOST_DEVICE void operator()(Index n) const { keep[n] = wall.signed_distance(points[n]) >= clearance ? 1u : 0u; }
};

template <int D>
struct GatherKept {
  View<const Vec<Real, D>> points;
  View<const std::uint32_t> keep, slot;
  View<Vec<Real, D>> kept;
  UNISPH_HOST_DEVICE void operator()(Index n) const {
    if (keep[n]) kept[slot[n]] = points[n];
  }
};

template <int D>
struct LatticeParticles {
  std::vector<Vec<Real, D>> position;
  std::vector<Vec<Real, D>> normal;  // unit, out of the solid (walls only)
};

namespace detail {
template <int D>
LatticeBlock<D> lattice_block(const CompiledShape<D>& shape, Real dx, const LatticeOptions<D>& options) {
  if (!(dx > Real(0)) || !std::isfinite(dx)) throw ShapeError("shape: the lattice spacing must be positive, got " + text(dx));
  Box<Real, D> region = shape.bounds();
  if (options.region) {
    region.lower = max(region.lower, options.region->lower);
    region.upper = min(region.upper, options.region->upper);
  }
  LatticeBlock<D> block{};
  block.origin = options.origin;
  block.spacing = dx;
  double points = 1;
  for (int k = 0; k < D; ++k) {
    if (!std::isfinite(region.lower[k]) || !std::isfinite(region.upper[k]))
      throw ShapeError("shape: the lattice region is unbounded along axis " + std::to_string(k) +
                       " (the shape holds a half-space or a complement); give LatticeOptions::region");
    // In double, checked before converting: user coordinates far beyond the lattice's index range
    // must not overflow the conversion to an integer.
    const double first = std::ceil((double(region.lower[k]) - double(options.origin[k])) / double(dx) - 0.5);
    const double last = std::floor((double(region.upper[k]) - double(options.origin[k])) / double(dx) - 0.5);
    if (!(std::fabs(first) < 4e18 && std::fabs(last) < 4e18))
      throw ShapeError("shape: the lattice region " + text(region.lower) + " to " + text(region.upper) +
                       " spans too many spacings of " + text(dx));
    block.first[k] = (long long)first;
    block.count[k] = last >= first ? (long long)(last - first) + 1 : 0;
    points *= double(block.count[k]);
  }
  if (points >= double(std::numeric_limits<std::uint32_t>::max()))
    throw ShapeError("shape: the lattice over " + text(region.lower) + " to " + text(region.upper) + " at spacing " +
                     text(dx) + " has " + text(Real(points)) + " points, more than the 2^32 - 1 one pass handles");
  return block;
}

template <ExecutionPolicy P, int D>
LatticeParticles<D> select(P policy, CompiledShape<D>& shape, const LatticeBlock<D>& lattice, Real below, Real above,
                           Real normal_step) {
  const Index n = lattice.size();
  LatticeParticles<D> out;
  if (n == 0) return out;
  const ShapeView<D> view = shape.view(policy);
  DiscreteVariable<std::uint32_t> marked("LatticeMarked", n), slot("LatticeSlot", n);
  particle_for(policy, n, MarkLatticePoints<D>{view, lattice, below, above, marked.write(policy)});
  const Index count = particle_reduce(policy, n, Sum<Index>{}, CountMarked{marked.read(policy)});
  exclusive_scan(policy, marked, slot);
  DiscreteVariable<Vec<Real, D>> position("LatticePosition", count), normal("LatticeNormal", normal_step > 0 ? count : 0);
  particle_for(policy, n,
               GatherLatticePoints<D>{view, lattice, normal_step, marked.read(policy), slot.read(policy),
                                      position.write(policy), normal.write(policy)});
  out.position = position.to_vector();
  if (normal_step > Real(0)) out.normal = normal.to_vector();
  return out;
}
}  // namespace detail

// The lattice points in the shape (FillRule), in lattice order.
template <ExecutionPolicy P, int D>
std::vector<Vec<Real, D>> fill_with_particles(P policy, CompiledShape<D>& shape, Real dx,
                                              FillRule rule = FillRule::whole_cell,
                                              const LatticeOptions<D>& options = {}) {
  const LatticeBlock<D> lattice = detail::lattice_block(shape, dx, options);
  const Real above = rule == FillRule::whole_cell ? -(Real(0.5) - lattice_tolerance) * dx : Real(0);
  return detail::select(policy, shape, lattice, -std::numeric_limits<Real>::max(), above, Real(0)).position;
}

// The dummy wall particles of a solid: the lattice points inside it (signed distance < 0) less
// than `layers` dx deep, each with the unit normal out of the solid (central differences of the
// signed distance with a step of dx / 100). The depth is measured from the nearest surface of
// the solid, so a wall thinner than 2 layers dx is filled through.
template <ExecutionPolicy P, int D>
LatticeParticles<D> make_wall_particles(P policy, CompiledShape<D>& solid, Real dx, int layers = default_wall_layers,
                                        const LatticeOptions<D>& options = {}) {
  if (layers < 1) throw ShapeError("shape: a wall needs at least one layer, got " + std::to_string(layers));
  const LatticeBlock<D> lattice = detail::lattice_block(solid, dx, options);
  return detail::select(policy, solid, lattice, -Real(layers) * dx, Real(0), dx / Real(100));
}

// Removes from `fluid` the points within dx / 2 of the wall's surface or inside the wall (signed
// distance below dx / 2, less lattice_tolerance dx so that a point exactly dx / 2 from a wall,
// as on a shared lattice, stays). Keeps the order; returns how many were removed.
template <ExecutionPolicy P, int D>
Index remove_near_wall(P policy, std::vector<Vec<Real, D>>& fluid, CompiledShape<D>& wall, Real dx) {
  if (!(dx > Real(0)) || !std::isfinite(dx)) throw ShapeError("shape: the lattice spacing must be positive, got " + detail::text(dx));
  const Index n = fluid.size();
  if (n == 0) return 0;
  DiscreteVariable<Vec<Real, D>> points("FluidCandidates");
  points.assign(fluid);
  DiscreteVariable<std::uint32_t> keep("FluidKeep", n), slot("FluidSlot", n);
  particle_for(policy, n,
               MarkClearOfWall<D>{wall.view(policy), points.read(policy), (Real(0.5) - lattice_tolerance) * dx, keep.write(policy)});
  const Index kept_count = particle_reduce(policy, n, Sum<Index>{}, CountMarked{keep.read(policy)});
  exclusive_scan(policy, keep, slot);
  DiscreteVariable<Vec<Real, D>> kept("FluidKept", kept_count);
  particle_for(policy, n, GatherKept<D>{points.read(policy), keep.read(policy), slot.read(policy), kept.write(policy)});
  fluid = kept.to_vector();
  return n - kept_count;
}

}  // namespace unisph::shape
