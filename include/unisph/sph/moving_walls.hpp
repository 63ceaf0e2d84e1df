#pragma once
// Wall bodies that move by a prescribed rigid motion (motion/rigid_motion.hpp): a piston or flap
// paddle, a tank that sways or rolls. Each wall particle keeps its reference position and normal
// (where the motion is at rest) and the index of its body's motion; MoveWalls sets its position,
// normal, velocity and acceleration at a given time from the exact law, so the wall follows the
// law exactly at every step (no integration error accumulates).
//
// The walls' velocity and acceleration enter the fluid's wall terms (pressure_relaxation.hpp,
// density_relaxation.hpp, prior_acceleration.hpp): the Riemann jump and the continuity
// equation's mirror take the fluid's velocity relative to the wall, v_i - v_w, the dummy pressure
// extrapolates with the fluid's prior acceleration less the wall's, a0_i - a_w (the wall's
// frame accelerates: a fluid at rest relative to an accelerating tank has the pressure gradient
// rho (g - a_w)), and the viscous mirror velocity is 2 v_w - v_i. Static walls have v_w = a_w = 0,
// and a case without moving walls registers none of these variables (no memory per particle).
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/motion/rigid_motion.hpp"
#include "unisph/sph/fluid_variables.hpp"

namespace unisph::sph {

// The variables a moving wall adds to the wall body's particle set (sortable: they travel with
// the particles in a sort and are stored in checkpoints).
template <class T, int D>
struct WallMotionVariables {
  using Vector = Vec<T, D>;
  DiscreteVariable<Vector>& initial_position;  // where the particle is with its motion at rest
  DiscreteVariable<Vector>& initial_normal;
  DiscreteVariable<Vector>& velocity;
  DiscreteVariable<Vector>& acceleration;
  DiscreteVariable<std::uint32_t>& motion;  // index into the solver's motions (0: at rest)

  explicit WallMotionVariables(Body<T, D>& wall)
      : initial_position(wall.particles().template add_variable<Vector>("InitialPosition", sortable_variable)),
        initial_normal(wall.particles().template add_variable<Vector>("InitialNormal", sortable_variable)),
        velocity(wall.particles().template add_variable<Vector>("Velocity", sortable_output_variable)),
        acceleration(wall.particles().template add_variable<Vector>("Acceleration", sortable_variable)),
        motion(wall.particles().template add_variable<std::uint32_t>("Motion", sortable_variable)) {}
};

// A RigidMotion in a variable: its views (a table law's knots) have default member
// initialisers, so it is trivially copyable but not trivially default constructible, which a
// DiscreteVariable's element must be; the bytes are.
template <int D>
struct alignas(RigidMotion<D>) StoredRigidMotion {
  static_assert(std::is_trivially_copyable_v<RigidMotion<D>>, "A rigid motion is copied to the device byte for byte.");
  unsigned char bytes[sizeof(RigidMotion<D>)];
  static StoredRigidMotion of(const RigidMotion<D>& m) {
    StoredRigidMotion s;
    std::memcpy(s.bytes, &m, sizeof(m));
    return s;
  }
  UNISPH_HOST_DEVICE const RigidMotion<D>& get() const { return *reinterpret_cast<const RigidMotion<D>*>(bytes); }
};

// x, n, v, a of every wall particle at time t (the launch's scalar argument is the time).
template <class T, int D>
class MoveWalls : public UpdateDynamics<MoveWalls<T, D>> {
 public:
  MoveWalls(WallVariables<T, D>& wall, WallMotionVariables<T, D>& motion, DiscreteVariable<StoredRigidMotion<D>>& motions)
      : wall_(wall), motion_(motion), motions_(motions) {}

  struct Kernel {
    View<Vec<T, D>> position, normal, velocity, acceleration;
    View<const Vec<T, D>> initial_position, initial_normal;
    View<const std::uint32_t> motion;
    View<const StoredRigidMotion<D>> motions;

    UNISPH_HOST_DEVICE void update(Index i, Real time) const {
      const RigidMotion<D>& m = motions[motion[i]].get();
      Vecd<D> x0, n0;
      for (int a = 0; a < D; ++a) x0[a] = Real(initial_position[i][a]), n0[a] = Real(initial_normal[i][a]);
      const PointMotion<D> state = m(x0, time);
      const Vecd<D> n = m.rotate(n0, time);
      Vec<T, D> x, nn, v, acc;
      for (int a = 0; a < D; ++a) {
        x[a] = T(state.position[a]);
        nn[a] = T(n[a]);
        v[a] = T(state.velocity[a]);
        acc[a] = T(state.acceleration[a]);
      }
      position[i] = x;
      normal[i] = nn;
      velocity[i] = v;
      acceleration[i] = acc;
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");

  Kernel make_kernel(KernelContext& c) {
    return {c.write(wall_.position),          c.write(wall_.normal),         c.write(motion_.velocity),
            c.write(motion_.acceleration),    c.read(motion_.initial_position), c.read(motion_.initial_normal),
            c.read(motion_.motion),           c.read(motions_)};
  }
  // Owned wall particles and ghosts: a ghost from another rank (solver/rank_share.hpp) carries
  // its reference state and motion, and follows the law here as it does on its owner.
  Index size() const { return wall_.particles.total_count(); }

 private:
  WallVariables<T, D>& wall_;
  WallMotionVariables<T, D>& motion_;
  DiscreteVariable<StoredRigidMotion<D>>& motions_;
};

}  // namespace unisph::sph
