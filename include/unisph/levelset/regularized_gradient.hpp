#pragma once
// The gradient of a field on a package mesh by a regularised central difference: per axis the
// mean of the forward and backward differences, except where they disagree in sign (a ridge or
// valley of the distance, e.g. the medial axis), where the larger one in magnitude is kept so
// that the normal does not vanish there. Stencils cross package borders through
// neighbour_index_shift.

#include <cstdint>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/grid/neighbour_index_shift.hpp"
#include "unisph/memory/view.hpp"

namespace unisph {

UNISPH_HOST_DEVICE inline Real regularize_difference(Real forward, Real backward) {
  if (forward * backward >= Real(0)) return Real(0.5) * (forward + backward);
  return (forward > Real(0) ? forward : -forward) > (backward > Real(0) ? backward : -backward) ? forward : backward;
}

template <int D>
UNISPH_HOST_DEVICE inline Vec<Real, D> regularized_gradient(View<const Real> field, const PackageNeighbourhood<D>& around,
                                                            std::uint32_t package, int local_point, Real spacing) {
  Vec<int, D> local;
  int rest = local_point;
  for (int k = 0; k < D; ++k) {
    local[k] = rest % package_size;
    rest /= package_size;
  }
  const Real centre = field[Index(package) * package_points<D> + local_point];
  Vec<Real, D> gradient;
  for (int k = 0; k < D; ++k) {
    Vec<int, D> plus = local, minus = local;
    plus[k] += 1;
    minus[k] -= 1;
    const DataPointAddress p = neighbour_index_shift<D>(plus, around), m = neighbour_index_shift<D>(minus, around);
    const Real forward = field[Index(p.package) * package_points<D> + p.local_point] - centre;
    const Real backward = centre - field[Index(m.package) * package_points<D> + m.local_point];
    gradient[k] = regularize_difference(forward, backward) / spacing;
  }
  return gradient;
}

}  // namespace unisph
