#pragma once
// Per-particle updates of an acoustic step that no barrier separates, run in one launch each
// (every policy). Each fused kernel holds the kernels of its parts and calls them in the order
// the solver called them, particle by particle, so the values are the same bits as the
// separate launches give:
//
//   VelocityUpdateAndMaxSpeed        VelocityUpdate (v += (a + a0) dt, x += v dt/2), then
//                                    the largest |v| (MaximumSpeed) of the updated velocities:
//                                    the time step of the next acoustic step is known before
//                                    the density relaxation, without a launch of its own.
//   DensityUpdateAndPressureStart    DensityUpdate of step n (rho += drho/dt dt_n/2), then
//                                    PressureRelaxationStart of step n + 1 (rho += drho/dt
//                                    dt_n+1/2, p = EOS(rho), x += v dt_n+1/2).
//
// An acoustic step is then four launches (pressure relaxation, velocity update with the speed
// reduction, density relaxation, density update with the next step's start) instead of six;
// on the host with 3,200 particles a launch costs about as much as these updates' work.
#include <type_traits>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/sph/density_relaxation.hpp"
#include "unisph/sph/pressure_relaxation.hpp"
#include "unisph/sph/time_step.hpp"

namespace unisph::sph {

template <class T, int D>
class VelocityUpdateAndMaxSpeed : public ReduceDynamics<VelocityUpdateAndMaxSpeed<T, D>, Max<T>> {
 public:
  VelocityUpdateAndMaxSpeed(VelocityUpdate<T, D>& update, MaximumSpeed<T, D>& speed) : update_(update), speed_(speed) {}
  struct Kernel {
    typename VelocityUpdate<T, D>::Kernel update;
    typename MaximumSpeed<T, D>::Kernel speed;
    UNISPH_HOST_DEVICE T reduce(Index i, Real dt) const {
      update.update(i, dt);
      return speed.reduce(i, dt);
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  Kernel make_kernel(KernelContext& c) { return {update_.make_kernel(c), speed_.make_kernel(c)}; }
  Index size() const { return update_.size(); }
  T finish(T squared) const { return speed_.finish(squared); }

 private:
  VelocityUpdate<T, D>& update_;
  MaximumSpeed<T, D>& speed_;
};

template <class T, int D>
class DensityUpdateAndPressureStart : public KernelShell<DensityUpdateAndPressureStart<T, D>> {
 public:
  DensityUpdateAndPressureStart(DensityUpdate<T, D>& finish, PressureRelaxationStart<T, D>& start)
      : finish_(finish), start_(start) {}
  struct Kernel {
    typename DensityUpdate<T, D>::Kernel finish;
    typename PressureRelaxationStart<T, D>::Kernel start;
    UNISPH_HOST_DEVICE void update(Index i, Real dt_finished, Real dt_next) const {
      finish.update(i, dt_finished);
      start.update(i, dt_next);
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  struct Launch {
    Kernel kernel;
    Real dt_finished, dt_next;
    UNISPH_HOST_DEVICE void operator()(Index i) const { kernel.update(i, dt_finished, dt_next); }
  };
  Kernel make_kernel(KernelContext& c) { return {finish_.make_kernel(c), start_.make_kernel(c)}; }
  Index size() const { return finish_.size(); }

  // Finishes the step of dt_finished and starts the one of dt_next.
  template <ExecutionPolicy P>
  void exec(P policy, Real dt_finished, Real dt_next) {
    const Kernel& k = this->kernel(policy);
    particle_for(policy, size(), Launch{k, dt_finished, dt_next});
  }

 private:
  DensityUpdate<T, D>& finish_;
  PressureRelaxationStart<T, D>& start_;
};

}  // namespace unisph::sph
