#pragma once
// Damping of the fluid's velocity, v *= keep, for the settling stage that puts a case's water
// into the equilibrium of the discrete forces before its time 0 (docs/sph.md, "Settling").
//
// Why it is needed: the square lattice the water is made on is not a stable equilibrium of the
// pair pressure force at h = 1.3 dx (docs/validation.md, "The hydrostatic tank's
// instability"); water started on it leaves it. Settled under damping, it comes to rest where
// the discrete forces balance and the lattice's sliding mode has already run its course.
#include <type_traits>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/sph/neighbor_records.hpp"

namespace unisph::sph {

template <class T, int D>
class VelocityDamping : public UpdateDynamics<VelocityDamping<T, D>> {
 public:
  explicit VelocityDamping(FluidVariables<T, D>& fluid) : fluid_(fluid) {}
  struct Kernel {
    View<const Vec<T, D>> position;
    View<Vec<T, D>> velocity;
    View<const T> pressure, mass, density;
    NeighborRecordWriter<T, D> records;  // the records carry v, so they follow it
    // `keep` = exp(-rate dt), passed where the solver passes a step.
    UNISPH_HOST_DEVICE void update(Index i, Real keep) const {
      const Vec<T, D> v = velocity[i] * T(keep);
      velocity[i] = v;
      records.store(i, position[i], v, pressure[i], mass[i], density[i]);
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  Kernel make_kernel(KernelContext& c) {
    return {c.read(fluid_.position),
            c.read_write(fluid_.velocity),
            c.read(fluid_.pressure),
            c.read(fluid_.mass),
            c.read(fluid_.density),
            NeighborRecordWriter<T, D>::make(c, fluid_)};
  }
  Index size() const { return fluid_.size(); }

 private:
  FluidVariables<T, D>& fluid_;
};

}  // namespace unisph::sph
