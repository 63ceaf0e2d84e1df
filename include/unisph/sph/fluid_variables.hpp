#pragma once
// The named variables of a weakly compressible fluid body and of a wall body. The fluid's state
// variables are sortable (they move with the particles when the set is reordered, migrate between
// ranks and are in checkpoints) and the physical ones are written to the output; its two
// neighbour records are derived from them. The two accelerations are neither: each is written
// whole before it is read within a step (the pressure acceleration by every pressure relaxation,
// the prior one at the start of every advection step), so a sort need not move them (24 bytes
// per particle in 3D float less to permute at every advection step).
#include "unisph/particles/body.hpp"

namespace unisph::sph {

// Derived neighbour records (neighbor_records.hpp): what a relaxation pair reads of neighbour j
// in one aligned 16-byte load each (two for double in 3D).
template <class T, int D>
struct alignas(16) PositionVolume {
  Vec<T, D> position;
  T volume;  // m / rho
};
template <class T, int D>
struct alignas(16) VelocityPressure {
  Vec<T, D> velocity;
  T pressure;
};

template <class T, int D>
struct FluidVariables {
  using Vector = Vec<T, D>;
  ParticleSet& particles;  // declared first: initialised first
  DiscreteVariable<Vector>& position;
  DiscreteVariable<Vector>& velocity;
  DiscreteVariable<Vector>& acceleration;        // from pressure, per acoustic step (not sorted)
  DiscreteVariable<Vector>& prior_acceleration;  // gravity and viscosity, per advection step (not sorted)
  DiscreteVariable<T>& density;
  DiscreteVariable<T>& pressure;
  DiscreteVariable<T>& mass;
  DiscreteVariable<T>& density_change_rate;
  // Derived, neither sorted nor output nor in checkpoints: refreshed by the kernels that change
  // x, v, p or rho and after a sort or a restore (neighbor_records.hpp).
  DiscreteVariable<PositionVolume<T, D>>& neighbor_position_volume;
  DiscreteVariable<VelocityPressure<T, D>>& neighbor_velocity_pressure;

  explicit FluidVariables(Body<T, D>& body)
      : particles(body.particles()),
        position(body.positions()),
        velocity(body.particles().template add_variable<Vector>("Velocity", sortable_output_variable)),
        acceleration(body.particles().template add_variable<Vector>("Acceleration")),
        prior_acceleration(body.particles().template add_variable<Vector>("PriorAcceleration")),
        density(body.particles().template add_variable<T>("Density", sortable_output_variable)),
        pressure(body.particles().template add_variable<T>("Pressure", sortable_output_variable)),
        mass(body.particles().template add_variable<T>("Mass", sortable_output_variable)),
        density_change_rate(body.particles().template add_variable<T>("DensityChangeRate", sortable_variable)),
        neighbor_position_volume(
            body.particles().template add_variable<PositionVolume<T, D>>("NeighborPositionVolume")),
        neighbor_velocity_pressure(
            body.particles().template add_variable<VelocityPressure<T, D>>("NeighborVelocityPressure")) {}

  // The owned particles: every update, interaction and reduction runs over these. Ghosts (the
  // images of a periodic axis, neighbor/periodic_images.hpp) follow them, read as neighbours only.
  Index size() const { return particles.owned_count(); }
  // Owned particles and ghosts.
  Index total_size() const { return position.size(); }
};

// A static wall of dummy particles: positions and unit normals pointing into the fluid.
template <class T, int D>
struct WallVariables {
  using Vector = Vec<T, D>;
  ParticleSet& particles;
  DiscreteVariable<Vector>& position;
  DiscreteVariable<Vector>& normal;
  // Moving walls only (moving_walls.hpp): each particle's velocity and acceleration; null where
  // every wall is at rest, and the kernels then take v_w = a_w = 0.
  DiscreteVariable<Vector>* velocity = nullptr;
  DiscreteVariable<Vector>* acceleration = nullptr;
  // fluid.wall_pressure = "averaged" only (wall_pressure_average.hpp): each wall particle's
  // pressure, averaged from its fluid neighbours; null where each pair extrapolates the fluid
  // particle's own (wall_dummy_pressure.hpp).
  DiscreteVariable<T>* pressure = nullptr;

  explicit WallVariables(Body<T, D>& body)
      : particles(body.particles()),
        position(body.positions()),
        normal(body.particles().template add_variable<Vector>("Normal", sortable_output_variable)) {}

  Index size() const { return particles.owned_count(); }  // without the images of periodic axes
  bool moving() const { return velocity != nullptr; }

  // The views of the walls' velocity and acceleration for a kernel (empty for static walls).
  template <class Context>
  View<const Vector> velocity_view(Context& c) const { return velocity ? c.read(*velocity) : View<const Vector>{}; }
  template <class Context>
  View<const Vector> acceleration_view(Context& c) const {
    return acceleration ? c.read(*acceleration) : View<const Vector>{};
  }
  // The walls' own pressures for a kernel (empty: extrapolated per pair).
  template <class Context>
  View<const T> pressure_view(Context& c) const {
    return pressure ? c.read(*pressure) : View<const T>{};
  }
};

}  // namespace unisph::sph
