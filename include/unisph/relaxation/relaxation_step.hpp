#pragma once
// RelaxationStep<D>: moves every particle along its residual with momentum (heavy ball),
//   v_i = momentum v_i + step a_i,   x_i += v_i,
// and puts those that crossed the surface back onto it (RelaxationSurface::bound). The step is the same for
// all particles and is passed to exec as `dt` (ParticleRelaxation chooses it from the largest
// residual, see particle_relaxation.hpp).
//
// ResidualNorms<D>: the largest |a_i| and the sum of |a_i| in one reduction.
//
// Both reductions (these norms and FIRE's PowerAndNorms) decide the next step (FIRE's time
// step, restarts, the final descent's β), so they use deterministic_reduce: the same bits on
// every policy, which keeps the trajectories of seq, par and the GPU equal bit for bit.

#include <cmath>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/relaxation/owned_particles.hpp"
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

  // FIRE (Bitzek et al. 2006) for the next exec: the velocities mixed towards the residual by
  // `mixing` (alpha) with `steer` = alpha |v| / |a| (norms over all particles), or dropped when
  // `restart` (and, with `particle_restart`, for each particle whose residual points against its
  // velocity); then v += dt a, x += dt v. exec's dt is then FIRE's time step, not β.
  void set_fire(Real mixing, Real steer, bool restart, bool particle_restart = false) {
    fire_ = true;
    particle_restart_ = particle_restart;
    mixing_ = mixing;
    steer_ = steer;
    restart_ = restart;
    this->invalidate_kernels();
  }
  void set_descent() {
    fire_ = false;
    this->invalidate_kernels();
  }

  struct Kernel {
    View<Position> position;
    View<Position> velocity;
    View<const Position> residual;
    RelaxationSurface<D> surface;
    Real momentum;
    bool fire;
    Real mixing, steer;
    bool restart;
    bool particle_restart;
    UNISPH_HOST_DEVICE void update(Index i, Real step) const {
      if (fire) {
        const Position a = residual[i];
        // On a restart the particle first goes back half of its last move (FIRE 2.0,
        // Guénolé et al. 2020): the last step overshot the minimum along v; step is then half
        // the last one, so half the last move is step * v.
        const Position start = restart ? position[i] - velocity[i] * step : position[i];
        const bool stop = restart || (particle_restart && dot(velocity[i], a) < Real(0));
        Position v = stop ? Position{} : velocity[i] * (Real(1) - mixing) + a * steer;
        v += a * step;
        const Position moved = start + v * step;
        const Position bounded = surface.bound(moved);
        velocity[i] = bounded == moved ? v : Position{};
        position[i] = bounded;
        return;
      }
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
    return {context.read_write(position_), context.read_write(velocity_), context.read(residual_), surface_, momentum_,
            fire_, mixing_, steer_, restart_, particle_restart_};
  }
  // Periodic relaxation: the set holds images after its owned particles; only those move.
  void count_owned_of(const ParticleSet& set) { owned_.count_owned_of(set); }
  Index size() const { return owned_.count(position_.size()); }

 private:
  OwnedParticles owned_;
  DiscreteVariable<Position>& position_;
  DiscreteVariable<Position>& velocity_;
  DiscreteVariable<Position>& residual_;
  Real momentum_;
  RelaxationSurface<D> surface_{};
  bool fire_ = false;
  Real mixing_ = Real(0), steer_ = Real(0);
  bool restart_ = false;
  bool particle_restart_ = false;
};

// FIRE's global quantities in one reduction: (Σ a_i·v_i, Σ |a_i|², Σ |v_i|²).
template <int D>
class PowerAndNorms : public ReduceDynamics<PowerAndNorms<D>, Sum<Vec<Real, 3>>, ReduceOrder::fixed> {
 public:
  PowerAndNorms(DiscreteVariable<Vec<Real, D>>& residual, DiscreteVariable<Vec<Real, D>>& velocity)
      : residual_(residual), velocity_(velocity) {}
  struct Kernel {
    View<const Vec<Real, D>> residual;
    View<const Vec<Real, D>> velocity;
    UNISPH_HOST_DEVICE Vec<Real, 3> reduce(Index i, Real) const {
      return Vec<Real, 3>{{dot(residual[i], velocity[i]), dot(residual[i], residual[i]), dot(velocity[i], velocity[i])}};
    }
  };
  Kernel make_kernel(KernelContext& context) { return {context.read(residual_), context.read(velocity_)}; }
  // Periodic relaxation: the images after the owned particles are not counted.
  void count_owned_of(const ParticleSet& set) { owned_.count_owned_of(set); }
  Index size() const { return owned_.count(residual_.size()); }

 private:
  OwnedParticles owned_;
  DiscreteVariable<Vec<Real, D>>& residual_;
  DiscreteVariable<Vec<Real, D>>& velocity_;
};

// (largest, sum) combined in one pass; the sum makes the mean.
struct MaxAndSum {
  UNISPH_HOST_DEVICE static constexpr Vec<Real, 2> identity() { return Vec<Real, 2>{}; }
  UNISPH_HOST_DEVICE constexpr Vec<Real, 2> operator()(const Vec<Real, 2>& a, const Vec<Real, 2>& b) const {
    return Vec<Real, 2>{{a[0] > b[0] ? a[0] : b[0], a[1] + b[1]}};
  }
};

template <int D>
class ResidualNorms : public ReduceDynamics<ResidualNorms<D>, MaxAndSum, ReduceOrder::fixed> {
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
  // Periodic relaxation: the images after the owned particles are not counted.
  void count_owned_of(const ParticleSet& set) { owned_.count_owned_of(set); }
  Index size() const { return owned_.count(residual_.size()); }

 private:
  OwnedParticles owned_;
  DiscreteVariable<Vec<Real, D>>& residual_;
};

}  // namespace unisph
