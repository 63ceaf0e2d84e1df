#pragma once
// Observers of a fluid body, each a reduction over the fluid particles:
//   PressureProbe      kernel-averaged (Shepard) pressure at a point: sum p_j W V_j / sum W V_j
//   FrontPosition      the largest coordinate along an axis, plus dx/2 (the particle's half
//                      width: a column of n particles has its front at n dx)
//   MechanicalEnergy   kinetic sum m v^2/2 and potential sum -m g.x
#include <type_traits>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/exec/reduce_ops.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"

namespace unisph::sph {

template <class T, int D>
class PressureProbe : public ReduceDynamics<PressureProbe<T, D>, Sum<Vec<T, 2>>> {
 public:
  // `ghosts_are_images`: ghosts are the images of periodic axes, which the probe reads; false
  // where they are copies of other ranks' particles, which those ranks count (sums()). Then
  // `period` (0 along the axes that are not periodic) gives the owned particles' nearest image.
  PressureProbe(FluidVariables<T, D>& fluid, WendlandC2Kernel<T, D> kernel, Vec<T, D> point,
                bool ghosts_are_images = true, Vec<T, D> period = Vec<T, D>{})
      : fluid_(fluid), kernel_(kernel), point_(point), period_(period), ghosts_are_images_(ghosts_are_images) {}
  struct Kernel {
    View<const Vec<T, D>> position;
    View<const T> pressure, density, mass;
    WendlandC2Kernel<T, D> kernel;
    Vec<T, D> point;
    Vec<T, D> period;
    UNISPH_HOST_DEVICE Vec<T, 2> reduce(Index i, Real) const {
      Vec<T, D> r = point - position[i];
      for (int a = 0; a < D; ++a) {
        if (!(period[a] > T(0))) continue;
        if (r[a] > period[a] / T(2)) r[a] -= period[a];
        else if (r[a] < -period[a] / T(2)) r[a] += period[a];
      }
      const T r2 = squared_norm(r);
      const T cutoff = kernel.cutoff();
      if (r2 >= cutoff * cutoff) return Vec<T, 2>{};
      const T weight = kernel.value(std::sqrt(r2)) * mass[i] / density[i];
      return Vec<T, 2>{{pressure[i] * weight, weight}};
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  Kernel make_kernel(KernelContext& c) {
    return {c.read(fluid_.position), c.read(fluid_.pressure), c.read(fluid_.density), c.read(fluid_.mass), kernel_,
            point_, ghosts_are_images_ ? Vec<T, D>{} : period_};
  }
  // Owned particles and ghosts: a probe near a periodic face sees the images across it (their
  // pressure, density and mass refreshed by the caller).
  Index size() const { return ghosts_are_images_ ? fluid_.total_size() : fluid_.size(); }
  // No fluid particle near the probe: the pressure there is zero (a free surface).
  T finish(Vec<T, 2> sums) const { return sums[1] > T(0) ? sums[0] / sums[1] : T(0); }
  // The two sums that finish() divides (sum p W V, sum W V), for a probe whose particles are
  // spread over ranks: add the ranks' sums, then divide.
  template <ExecutionPolicy P>
  Vec<T, 2> sums(P policy) {
    return deterministic_reduce(policy, size(), Sum<Vec<T, 2>>{}, detail::ReduceLaunch<Kernel>{this->kernel(policy), Real(0)});
  }

 private:
  FluidVariables<T, D>& fluid_;
  WendlandC2Kernel<T, D> kernel_;
  Vec<T, D> point_;
  Vec<T, D> period_;
  bool ghosts_are_images_;
};

template <class T, int D>
class FrontPosition : public ReduceDynamics<FrontPosition<T, D>, Max<T>> {
 public:
  FrontPosition(FluidVariables<T, D>& fluid, int axis, T dx) : fluid_(fluid), axis_(axis), half_dx_(T(0.5) * dx) {}
  struct Kernel {
    View<const Vec<T, D>> position;
    int axis;
    UNISPH_HOST_DEVICE T reduce(Index i, Real) const { return position[i][axis]; }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  Kernel make_kernel(KernelContext& c) { return {c.read(fluid_.position), axis_}; }
  Index size() const { return fluid_.size(); }
  T finish(T largest) const { return largest + half_dx_; }

 private:
  FluidVariables<T, D>& fluid_;
  int axis_;
  T half_dx_;
};

template <class T, int D>
class MechanicalEnergy : public ReduceDynamics<MechanicalEnergy<T, D>, Sum<Vec<T, 2>>> {
 public:
  MechanicalEnergy(FluidVariables<T, D>& fluid, Vec<T, D> gravity) : fluid_(fluid), gravity_(gravity) {}
  struct Kernel {
    View<const Vec<T, D>> position, velocity;
    View<const T> mass;
    Vec<T, D> gravity;
    UNISPH_HOST_DEVICE Vec<T, 2> reduce(Index i, Real) const {
      return Vec<T, 2>{{T(0.5) * mass[i] * squared_norm(velocity[i]), -mass[i] * dot(gravity, position[i])}};
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  Kernel make_kernel(KernelContext& c) {
    return {c.read(fluid_.position), c.read(fluid_.velocity), c.read(fluid_.mass), gravity_};
  }
  Index size() const { return fluid_.size(); }

 private:
  FluidVariables<T, D>& fluid_;
  Vec<T, D> gravity_;
};

// Total mass, to check that it is conserved.
template <class T, int D>
class TotalMass : public ReduceDynamics<TotalMass<T, D>, Sum<T>> {
 public:
  explicit TotalMass(FluidVariables<T, D>& fluid) : fluid_(fluid) {}
  struct Kernel {
    View<const T> mass;
    UNISPH_HOST_DEVICE T reduce(Index i, Real) const { return mass[i]; }
  };
  Kernel make_kernel(KernelContext& c) { return {c.read(fluid_.mass)}; }
  Index size() const { return fluid_.size(); }

 private:
  FluidVariables<T, D>& fluid_;
};

}  // namespace unisph::sph
