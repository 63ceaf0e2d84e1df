#pragma once
// The ghosts' copy of what the relaxations read of a fluid neighbour j, for a periodic domain
// (neighbor/periodic_images.hpp): before each pressure or density relaxation pass, ghost g
// (slot owned + g, the image of owned particle s = sources[g] under image code c = codes[g])
// takes its source's position shifted by the image's shift, and its source's neighbour records
// (neighbor_records.hpp) with the same shifted position. One launch over the ghosts replaces
// three (the positions, then each record): the relaxations' neighbour reads (x_j, V_j, v_j, p_j)
// are then the source's, seen across the face.
#include <cstdint>
#include <type_traits>

#include "unisph/core/uncontracted_arithmetic.hpp"
#include "unisph/sph/neighbor_records.hpp"

namespace unisph::sph {

template <int D>
inline constexpr unsigned image_code_count = D == 2 ? 9u : 27u;  // 3^D (periodic_images.hpp)

template <class T, int D>
struct RefreshImageRecords {
  View<const std::uint32_t> sources, codes;
  View<Vec<T, D>> position;
  View<PositionVolume<T, D>> position_volume;
  View<VelocityPressure<T, D>> velocity_pressure;
  // shift[c] = the displacement of image code c: 0 or +-L per axis (PeriodicImages::shift); a
  // coordinate plus 0 or +-L is one correctly rounded add, the bits PeriodicImages::refresh gives.
  Vec<T, D> shift[image_code_count<D>];
  Index owned;
  UNISPH_HOST_DEVICE void operator()(Index g) const {
    const Index s = sources[g];
    const Vec<T, D> d = shift[codes[g]];
    Vec<T, D> x = position[s];
    for (int a = 0; a < D; ++a)
      if (d[a] != T(0)) x[a] = uncontracted::add(x[a], d[a]);
    const Index k = owned + g;
    position[k] = x;
    PositionVolume<T, D> pv = position_volume[s];
    pv.position = x;
    position_volume[k] = pv;
    velocity_pressure[k] = velocity_pressure[s];
  }
};
static_assert(std::is_trivially_copyable_v<RefreshImageRecords<float, 3>>, "Kernels are copied to the device byte for byte.");

// Several ranks with periodic axes: the halo shifts a periodic image's position, and its record
// arrives with its source's; ghost g (slot first + g) takes its own position into its record,
// the bits RefreshImageRecords gives an image on one rank (its source's position plus the shift).
template <class T, int D>
struct GhostRecordPositions {
  View<const Vec<T, D>> position;
  View<PositionVolume<T, D>> position_volume;
  Index first;
  UNISPH_HOST_DEVICE void operator()(Index g) const { position_volume[first + g].position = position[first + g]; }
};
static_assert(std::is_trivially_copyable_v<GhostRecordPositions<float, 3>>, "Kernels are copied to the device byte for byte.");

}  // namespace unisph::sph
