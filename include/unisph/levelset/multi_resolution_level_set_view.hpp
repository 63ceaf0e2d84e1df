#pragma once
// Probes of a multi-resolution level set inside kernels: phi and the normal at any position,
// from the finest layer whose interpolation stencil there lies wholly in packages with data,
// else from the next coarser one; where no layer resolves the point, the coarsest layer's
// interpolation with the far-field values mixed in (the far-field packages carry the side, so
// the sign stays right; beyond the grid: outside).

#include <type_traits>

#include "unisph/core/config.hpp"
#include "unisph/levelset/level_set_layer_view.hpp"

namespace unisph {

inline constexpr int max_level_set_layers = 8;

template <int D>
struct MultiResolutionLevelSetView {
  LevelSetLayerView<D> layer[max_level_set_layers];
  int levels;

  // The finest layer that resolves x, or -1.
  UNISPH_HOST_DEVICE int resolving_layer(const Vec<Real, D>& x) const {
    for (int level = levels - 1; level >= 0; --level)
      if (layer[level].resolves(x)) return level;
    return -1;
  }
  UNISPH_HOST_DEVICE Real probe_phi(const Vec<Real, D>& x) const {
    const int level = resolving_layer(x);
    return layer[level >= 0 ? level : 0].probe_phi(x);
  }
  UNISPH_HOST_DEVICE Real probe_kernel_weight(const Vec<Real, D>& x) const {
    const int level = resolving_layer(x);
    return layer[level >= 0 ? level : 0].probe_kernel_weight(x);
  }
  UNISPH_HOST_DEVICE Vec<Real, D> probe_kernel_gradient(const Vec<Real, D>& x) const {
    const int level = resolving_layer(x);
    return level >= 0 ? layer[level].probe_kernel_gradient(x) : Vec<Real, D>{};
  }
  // Weight and gradient together, C1 and consistent (LevelSetLayerView::probe_kernel_integrals);
  // where no layer resolves x, the coarsest layer's weight by linear interpolation (the far
  // field's 0 or 1 there) and no gradient.
  UNISPH_HOST_DEVICE typename LevelSetLayerView<D>::KernelIntegrals probe_kernel_integrals(const Vec<Real, D>& x) const {
    const int level = resolving_layer(x);
    if (level >= 0) return layer[level].probe_kernel_integrals(x);
    return {layer[0].probe_kernel_weight(x), Vec<Real, D>{}};
  }
  UNISPH_HOST_DEVICE Vec<Real, D> probe_normal(const Vec<Real, D>& x) const {
    const int level = resolving_layer(x);
    return level >= 0 ? layer[level].probe_normal(x) : Vec<Real, D>{};
  }
};
static_assert(std::is_trivially_copyable_v<MultiResolutionLevelSetView<3>>,
              "a level-set view is captured by value into kernels, so it must be trivially copyable.");

}  // namespace unisph
