#pragma once
// WallPressureAverage: each wall dummy particle's pressure as a kernel average over its fluid
// neighbours, Adami et al.'s (2012) wall boundary, which TrixiParticles' dam break uses:
//
//   p_w = sum_f [ p_f + rho_f (g - a_w).(x_w - x_f) ] W_wf / sum_f W_wf,   clipped at 0,
//
// run before every momentum pass where the case asks for it (fluid.wall_pressure = "averaged").
// A fluid particle then meets one pressure per wall particle, shared by all its fluid
// neighbours, instead of its own pressure extrapolated along the pair (wall_dummy_pressure.hpp).
// Why it is offered: with the continuity density, the kernel-sum wall term and h = 1.75 dx it
// gives the dam break's wall pressure TrixiParticles' means and noise (docs/validation.md, "The
// peers' wall"). The clip keeps a wall from pulling water onto itself where the average is in
// tension (splashes); a wall particle without fluid neighbours gets 0.
//
// The fluid's cell list is searched from each wall particle's position (PointNeighbors), with the
// fluid's kernel. One rank, no periodic axis: the walls' pressures are not exchanged between
// ranks or images (the solver refuses those runs with one line).
#include <type_traits>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/neighbor/cell_linked_list.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/sph/point_neighbors.hpp"

namespace unisph::sph {

template <class T, int D>
class WallPressureAverage : public UpdateDynamics<WallPressureAverage<T, D>> {
 public:
  // Writes into `wall.pressure`, which the caller has set to a variable of the wall particles.
  WallPressureAverage(FluidVariables<T, D>& fluid, WallVariables<T, D>& wall, CellLinkedList<T, D>& fluid_cells,
                      WendlandC2Kernel<T, D> kernel, Vec<T, D> gravity)
      : fluid_(fluid), wall_(wall), cells_(fluid_cells), kernel_(kernel), gravity_(gravity) {}

  struct Kernel {
    PointNeighbors<T, D> fluid;
    View<const Vec<T, D>> wall_position;
    View<const Vec<T, D>> wall_acceleration;  // moving walls only (else empty)
    View<const PositionVolume<T, D>> position_volume;
    View<const VelocityPressure<T, D>> velocity_pressure;
    View<const T> density;
    View<T> wall_pressure;
    WendlandC2Kernel<T, D> kernel;
    Vec<T, D> gravity;
    UNISPH_HOST_DEVICE void update(Index w, Real) const {
      const Vec<T, D> x_w = wall_position[w];
      const Vec<T, D> g = wall_acceleration.size() > 0 ? Vec<T, D>(gravity - wall_acceleration[w]) : gravity;
      T weighted = T(0), weight = T(0);
      fluid.for_each(x_w, [&](Index j, T r) {
        const T W = kernel.value(r);
        weighted += W * (velocity_pressure[j].pressure + density[j] * dot(g, x_w - position_volume[j].position));
        weight += W;
      });
      const T p = weight > T(0) ? weighted / weight : T(0);
      wall_pressure[w] = p > T(0) ? p : T(0);
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");

  Kernel make_kernel(KernelContext& c) {
    return {PointNeighbors<T, D>::make(c, cells_),
            c.read(wall_.position),
            wall_.acceleration_view(c),
            c.read(fluid_.neighbor_position_volume),
            c.read(fluid_.neighbor_velocity_pressure),
            c.read(fluid_.density),
            c.write(*wall_.pressure),
            kernel_,
            gravity_};
  }
  Index size() const { return wall_.size(); }

 private:
  FluidVariables<T, D>& fluid_;
  WallVariables<T, D>& wall_;
  CellLinkedList<T, D>& cells_;
  WendlandC2Kernel<T, D> kernel_;
  Vec<T, D> gravity_;
};

}  // namespace unisph::sph
