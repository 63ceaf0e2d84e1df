#pragma once
// Dual-criteria time stepping with fixed CFL numbers (h the smoothing length):
//   advection step  Dt = 0.25 h / max(U, |v|max, mu/(rho0 h))   (neighbours and density summation)
//   acoustic step   dt = 0.6 h / (c0 + |v|max)                  (pressure and density relaxation)
// Both need |v|max, reduced over the fluid by MaximumSpeed.
#include <algorithm>
#include <cmath>
#include <type_traits>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/exec/reduce_ops.hpp"
#include "unisph/sph/fluid_variables.hpp"

namespace unisph::sph {

inline constexpr double advection_cfl = 0.25;
inline constexpr double acoustic_cfl = 0.6;

template <class T, int D>
class MaximumSpeed : public ReduceDynamics<MaximumSpeed<T, D>, Max<T>> {
 public:
  explicit MaximumSpeed(FluidVariables<T, D>& fluid) : fluid_(fluid) {}
  struct Kernel {
    View<const Vec<T, D>> velocity;
    UNISPH_HOST_DEVICE T reduce(Index i, Real) const { return squared_norm(velocity[i]); }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  Kernel make_kernel(KernelContext& c) { return {c.read(fluid_.velocity)}; }
  Index size() const { return fluid_.size(); }
  T finish(T squared) const { return std::sqrt(std::max(squared, T(0))); }

 private:
  FluidVariables<T, D>& fluid_;
};

struct TimeStepCriteria {
  double smoothing_length;
  double reference_speed;  // U
  double sound_speed;      // c0
  double kinematic_viscosity = 0;  // mu / rho0

  double advection_step(double max_speed) const {
    const double viscous_speed = kinematic_viscosity / smoothing_length;
    return advection_cfl * smoothing_length / std::max({reference_speed, max_speed, viscous_speed});
  }
  double acoustic_step(double max_speed) const { return acoustic_cfl * smoothing_length / (sound_speed + max_speed); }
};

}  // namespace unisph::sph
