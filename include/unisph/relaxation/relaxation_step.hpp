#pragma once
// RelaxationStep<D>: moves every particle along its residual with momentum (heavy ball),
//   v_i = momentum v_i + step a_i,   x_i += v_i,
// and puts those that crossed the surface back onto it (RelaxationSurface::bound). The step is the same for
// all particles and is passed to exec as `dt` (ParticleRelaxation chooses it from the largest
// residual, see particle_relaxation.hpp).
//
// ResidualNorms<D>: the largest |a_i| and the sum of |a_i| in one reduction.

#include <cmath>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/relaxation/relaxation_surface.hpp"

namespace unisph {

template <int D>
class RelaxationStep : public UpdateDynamics<RelaxationStep<D>> {
 public:
  using Position = Vec<Real, D>;

  RelaxationStep(DiscreteVariable<Position>& position, DiscreteVariable<Position>& velocity,
                 DiscreteVariable<Position>& residual, Real momentum)
      : position_(position), velocity_(velocity), residual_(residual), momentum_(momentum) {}

  void set_surface(const RelaxationSurface<D>& surface) {
    surface_ = surface;
    this->invalidate_kernels();
  }
  Real momentum() const { return momentum_; }
  void set_momentum(Real momentum) {
    momentum_ = momentum;
    this->invalidate_kernels();
  }

  struct Kernel {
    View<Position> position;
    View<Position> velocity;
    View<const Position> residual;
    RelaxationSurface<D> surface;
    Real momentum;
    UNISPH_HOST_DEVICE void update(Index i, Real step) const {
      // A particle whose residual turned against its motion has passed its minimum along it:
      // it drops the motion (a per-particle restart of the momentum, as in FIRE) instead of
      // oscillating about the minimum.
      const Position v = dot(velocity[i], residual[i]) < Real(0) ? Position{} : velocity[i];
      const Position move = v * momentum + residual[i] * step;
      const Position moved = position[i] + move;
      const Position bounded = surface.bound(moved);
      // A particle put back onto the surface forgets its motion (it would carry it outwards again).
      velocity[i] = bounded == moved ? move : Position{};
      position[i] = bounded;
    }
  };
  Kernel make_kernel(KernelContext& context) {
    return {context.read_write(position_), context.read_write(velocity_), context.read(residual_), surface_, momentum_};
  }
  Index size() const { return position_.size(); }

 private:
  DiscreteVariable<Position>& position_;
  DiscreteVariable<Position>& velocity_;
  DiscreteVariable<Position>& residual_;
  Real momentum_;
  RelaxationSurface<D> surface_{};
};

// (largest, sum) combined in one pass; the sum makes the mean.
struct MaxAndSum {
  UNISPH_HOST_DEVICE static constexpr Vec<Real, 2> identity() { return Vec<Real, 2>{}; }
  UNISPH_HOST_DEVICE constexpr Vec<Real, 2> operator()(const Vec<Real, 2>& a, const Vec<Real, 2>& b) const {
    return Vec<Real, 2>{{a[0] > b[0] ? a[0] : b[0], a[1] + b[1]}};
  }
};

template <int D>
class ResidualNorms : public ReduceDynamics<ResidualNorms<D>, MaxAndSum> {
 public:
  explicit ResidualNorms(DiscreteVariable<Vec<Real, D>>& residual) : residual_(residual) {}
  struct Kernel {
    View<const Vec<Real, D>> residual;
    UNISPH_HOST_DEVICE Vec<Real, 2> reduce(Index i, Real) const {
      const Real a = norm(residual[i]);
      return Vec<Real, 2>{{a, a}};
    }
  };
  Kernel make_kernel(KernelContext& context) { return {context.read(residual_)}; }
  Index size() const { return residual_.size(); }

 private:
  DiscreteVariable<Vec<Real, D>>& residual_;
};

}  // namespace unisph
