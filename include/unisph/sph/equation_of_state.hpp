#pragma once
// Weakly compressible equation of state: p = c0^2 (rho - rho0). The reference density and
// the artificial sound speed are the user's (any units).
#include "unisph/core/config.hpp"

namespace unisph::sph {

template <class T>
struct WeaklyCompressibleEquationOfState {
  T reference_density = T(1);
  T sound_speed = T(1);

  UNISPH_HOST_DEVICE T pressure(T density) const { return sound_speed * sound_speed * (density - reference_density); }
  UNISPH_HOST_DEVICE T density(T pressure) const {
    return reference_density + pressure / (sound_speed * sound_speed);
  }
};

}  // namespace unisph::sph
