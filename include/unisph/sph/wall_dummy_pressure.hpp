#pragma once
// The pressure a wall dummy particle w carries when it interacts with fluid particle i:
// the fluid's pressure extrapolated hydrostatically from i along the whole pair vector,
//   p_w = p_i + rho_i a0_i . (x_w - x_i) = p_i - rho_i a0_i . r_iw      (r_iw = x_i - x_w),
// with a0_i the prior (gravity) acceleration of i. The wall particles then continue the fluid's
// linear pressure field, so the kernel sums over fluid and wall together see a complete
// hydrostatic field: the momentum equation balances gravity beside a side wall (not only along
// its normal), and the Riemann velocity dissipation of the continuity equation, which is built
// on p_i - p_j, vanishes for water at rest next to a wall instead of compressing it.
// The momentum (PressureRelaxation) and continuity (DensityRelaxation) kernels must use the same
// wall pressure, hence one function.
// Where the wall particles carry a pressure of their own (fluid.wall_pressure = "averaged",
// wall_pressure_average.hpp), every pair takes that one instead: wall_pressure_of() decides, for
// the momentum, continuity and load kernels alike.
#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/memory/view.hpp"

namespace unisph::sph {

template <class T, int D>
UNISPH_HOST_DEVICE inline T wall_dummy_pressure(T fluid_pressure, T fluid_density, const Vec<T, D>& prior_acceleration,
                                                const Vec<T, D>& fluid_minus_wall) {
  return fluid_pressure - fluid_density * dot(prior_acceleration, fluid_minus_wall);
}

// Wall particle w's pressure for fluid particle i: its own where `averaged` holds one per wall
// particle (a uniform branch: every pair of a run takes the same side), else the extrapolation.
template <class T, int D>
UNISPH_HOST_DEVICE inline T wall_pressure_of(View<const T> averaged, Index w, T fluid_pressure, T fluid_density,
                                             const Vec<T, D>& prior_acceleration, const Vec<T, D>& fluid_minus_wall) {
  return averaged.size() > 0 ? averaged[w]
                             : wall_dummy_pressure(fluid_pressure, fluid_density, prior_acceleration, fluid_minus_wall);
}

}  // namespace unisph::sph
