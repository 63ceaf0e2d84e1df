#pragma once
// The level set a relaxation runs against, from a shape search (TriangleMeshSearch in 3D,
// PolygonSearch in 2D): finest spacing = the particle spacing dx (its kernel integrals then use
// the particles' smoothing length 1.3 dx), inside/outside by the generalized winding number
// (right next to inner walls and holes, where the pseudonormal is not: docs/levelset.md), over
// `box` padded by the kernel's cutoff so that every particle's support lies within it.

#include <memory>

#include "unisph/levelset/multi_resolution_level_set.hpp"
#include "unisph/core/box.hpp"

namespace unisph {

template <int D, ExecutionPolicy P>
std::unique_ptr<MultiResolutionLevelSet<D>> make_relaxation_level_set(P policy, ShapeSearch<D>& search,
                                                                      const Box<Real, D>& box, Real dx) {
  const Real pad = Real(2) * WendlandC2Kernel<Real, D>::smoothing_length_ratio * dx + dx;
  Vec<Real, D> lo = box.lower, hi = box.upper;
  for (int k = 0; k < D; ++k) {
    lo[k] -= pad;
    hi[k] += pad;
  }
  return std::make_unique<MultiResolutionLevelSet<D>>(policy, WindingNumberSign<ShapeSearchView<D>>{search.view(policy)},
                                                      lo, hi, dx);
}

}  // namespace unisph
