#pragma once
// Addressing data points across package borders. A package knows the 3^D packages around it
// (PackageNeighbourhood, slot (1, ..., 1) is the package itself); a data index relative to the
// package, each component in [-4, 8), names a point in the package or in one of those neighbours.
// NeighbourIndexShift turns it into (package, local point), so that finite differences and
// interpolation stencils read straight through borders without knowing where the borders are.

#include <cstdint>
#include <type_traits>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/grid/package_grid.hpp"

namespace unisph {

template <int D>
struct PackageNeighbourhood {
  std::uint32_t package[neighbourhood_size<D>];
};
static_assert(std::is_trivially_copyable_v<PackageNeighbourhood<3>>,
              "package neighbourhoods are copied to the device byte for byte: they must stay plain data.");

// The slot of the neighbour at offset (each component -1, 0 or 1).
template <int D>
UNISPH_HOST_DEVICE inline int neighbourhood_slot(const Vec<int, D>& offset) {
  int slot = offset[D - 1] + 1;
  for (int k = D - 2; k >= 0; --k) slot = slot * 3 + offset[k] + 1;
  return slot;
}

struct DataPointAddress {
  std::uint32_t package;
  int local_point;
};

template <int D>
UNISPH_HOST_DEVICE inline DataPointAddress neighbour_index_shift(const Vec<int, D>& relative_index,
                                                                 const PackageNeighbourhood<D>& neighbourhood) {
  Vec<int, D> offset, local;
  for (int k = 0; k < D; ++k) {
    // relative_index in [-4, 8): the shift is -1, 0 or 1 without a division.
    offset[k] = relative_index[k] < 0 ? -1 : (relative_index[k] >= package_size ? 1 : 0);
    local[k] = relative_index[k] - offset[k] * package_size;
  }
  return {neighbourhood.package[neighbourhood_slot<D>(offset)], local_point_index<D>(local)};
}

}  // namespace unisph
