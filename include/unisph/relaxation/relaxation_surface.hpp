#pragma once
// RelaxationSurface<D>: what the particles relax against, for use inside kernels — the part of a
// particle's kernel support that lies beyond the surface, and the rule that puts particles back.
//
// A particle near the surface lacks neighbours on the far side; the level set's kernel
// integrals stand in for them (Zhu et al. 2021):
//   missing weight    ∫_{beyond} W(x - y) dy
//   missing gradient  ∫_{beyond} ∇W(x - y) dy
// so that Σ_j W_ij V_j + weight ≈ 1 and Σ_j ∇W_ij V_j + gradient ≈ 0 for a uniform set.
// Both are probed together by cubic Hermite interpolation of the weight from the weight and
// the gradient at the data points (LevelSetLayerView::probe_kernel_integrals): the gradient is
// then the exact, continuous gradient of the weight, so the residual is the gradient of an
// energy (zero_order_residual.hpp) and the relaxation can converge to a state where it
// vanishes. (Linear interpolation of the two separately gives a gradient that is neither
// continuous nor the weight's: measured, the error then stalls near 7e-4 on the annulus.)
// "Beyond" is phi > 0 for particles inside a body (the level set's own integrals), phi < 0 for
// particles around it (1 - weight and -gradient, since W integrates to 1 and ∇W to 0).
//
// Around a body the particles also fill a box; each face of the box is a wall whose missing
// part is the half-space behind it, in closed form (HalfSpaceKernelIntegral). Where two faces
// meet, the quarter-space behind both is counted twice (edges and corners of the box are not
// corrected).
//
// bound(x): a particle closer to the surface than `gap` (or beyond it) is put back along the
// normal to the distance `gap` on its own side, x - (phi -+ gap) n (phi and n probed at x: exact
// for a plane). SPHinXsys keeps its particles half a spacing inside in the same way; with gap 0
// particles pressed outwards sit on the surface itself, where the surface term is weakest
// (measured: the largest residuals of the relaxed unit sphere were all there). Around a body
// the particles are also clamped into the box.

#include <type_traits>

#include "unisph/levelset/kernel_integrals.hpp"
#include "unisph/levelset/multi_resolution_level_set_view.hpp"
#include "unisph/core/box.hpp"

namespace unisph {

template <int D>
struct RelaxationSurface {
  MultiResolutionLevelSetView<D> level_set;
  bool particles_inside;           // true: a body's particles (phi < 0); false: around the body
  Box<Real, D> box;                // around a body: the box the particles fill
  HalfSpaceKernelIntegral<D> wall; // kernel integrals behind a face of the box
  Real gap;                        // particles are kept at least this far from the surface
  // No surface within reach of any particle (a fluid filling a periodic domain): nothing is
  // missing, and no particle is put back.
  bool none = false;

  struct Missing {
    Real weight;
    Vec<Real, D> gradient;  // the exact gradient of weight as a function of x
  };
  UNISPH_HOST_DEVICE Missing missing(const Vec<Real, D>& x) const {
    if (none) return {Real(0), Vec<Real, D>{}};
    const auto k = level_set.probe_kernel_integrals(x);
    if (particles_inside) return {k.weight, k.gradient};
    Missing m{Real(1) - k.weight, k.gradient * Real(-1)};
    for (int d = 0; d < D; ++d) {
      // signed distance from each face, positive behind it (outside the box); ∫ ∇_x W over
      // the half-space behind a face points from x towards that face
      m.weight += wall.weight(box.lower[d] - x[d]) + wall.weight(x[d] - box.upper[d]);
      m.gradient[d] += wall.marginal(x[d] - box.upper[d]) - wall.marginal(box.lower[d] - x[d]);
    }
    return m;
  }
  UNISPH_HOST_DEVICE Real missing_weight(const Vec<Real, D>& x) const { return missing(x).weight; }
  UNISPH_HOST_DEVICE Vec<Real, D> missing_gradient(const Vec<Real, D>& x) const { return missing(x).gradient; }

  // Signed distance from the surface, negative on the particles' side.
  UNISPH_HOST_DEVICE Real distance(const Vec<Real, D>& x) const {
    if (none) return Real(-1e30);
    const Real phi = level_set.probe_phi(x);
    return particles_inside ? phi : -phi;
  }

  UNISPH_HOST_DEVICE Vec<Real, D> bound(Vec<Real, D> x) const {
    if (none) return x;
    const Real phi = level_set.probe_phi(x);
    const Real target = particles_inside ? -gap : gap;
    if (particles_inside ? phi > target : phi < target) x -= level_set.probe_normal(x) * (phi - target);
    if (!particles_inside)
      for (int k = 0; k < D; ++k) {
        x[k] = x[k] < box.lower[k] ? box.lower[k] : x[k];
        x[k] = x[k] > box.upper[k] ? box.upper[k] : x[k];
      }
    return x;
  }
};
static_assert(std::is_trivially_copyable_v<RelaxationSurface<3>>,
              "a relaxation surface is captured by value into kernels, so it must be trivially copyable.");

}  // namespace unisph
