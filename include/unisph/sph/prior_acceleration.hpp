#pragma once
// The acceleration that stays fixed over an advection step: gravity (a vector in the
// user's units) plus, when the dynamic viscosity mu > 0, the laminar viscous term
//   a_i += sum_j 2 mu (v_i - v_j) / (rho_i (r_ij + 0.01 h) M) dW_ij V_j
// with no-slip walls (mirror velocity), M the operator's lattice moment
// (WendlandC2Kernel::lattice_laplacian_moment: 0.974 in 2D at h = 1.3 dx). Divided by M the
// operator gives the exact Laplacian on the particles' initial lattice, as the density summation
// divides by the lattice sum of W; without it the viscosity acted 2.7 % weakly (Poiseuille flow
// 3.0 % too fast, docs/sph.md).
#include <type_traits>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/neighbor/contact_relation.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"

namespace unisph::sph {

template <class T, int D>
class PriorAcceleration : public InteractionDynamics<PriorAcceleration<T, D>> {
 public:
  PriorAcceleration(FluidVariables<T, D>& fluid, WallVariables<T, D>& wall, InnerRelation<T, D>& inner,
                    ContactRelation<T, D>& contact, WendlandC2Kernel<T, D> kernel, Vec<T, D> gravity, T viscosity,
                    T wall_volume, T dx)
      : fluid_(fluid), wall_(wall), inner_(inner), contact_(contact), kernel_(kernel), gravity_(gravity),
        viscosity_(viscosity / kernel.lattice_laplacian_moment(dx, regularisation(kernel))), wall_volume_(wall_volume) {}

  UNISPH_HOST_DEVICE static T regularisation(const WendlandC2Kernel<T, D>& kernel) { return T(0.01) * kernel.h; }

  struct Kernel {
    // exec/occupancy_hint.hpp: 5 blocks of 256 in float, 3 in double.
    static constexpr int min_blocks_per_multiprocessor = sizeof(T) == 4 ? 5 : 3;
    NeighborSearch<T, D> inner, contact;
    View<const Vec<T, D>> velocity;
    View<const Vec<T, D>> wall_velocity;  // moving walls only (moving_walls.hpp; else empty)
    View<const T> density, mass;
    View<Vec<T, D>> prior_acceleration;
    WendlandC2Kernel<T, D> kernel;
    Vec<T, D> gravity;
    T viscosity, wall_volume;  // viscosity: mu / M (above)
    bool moving_walls;

    UNISPH_HOST_DEVICE void interaction(Index i, Real) const {
      Vec<T, D> a = gravity;
      if (viscosity > T(0)) {
        const Vec<T, D> v_i = velocity[i];
        const T regularisation = PriorAcceleration::regularisation(kernel);
        Vec<T, D> sum{};
        inner.for_each_neighbor(i, [&](Index j, const NeighborPair<T, D>& p) {
          const T r = p.distance();
          sum += (v_i - velocity[j]) * (kernel.derivative(r) * mass[j] / density[j] / (r + regularisation));
        });
        contact.for_each_neighbor(i, [&](Index w, const NeighborPair<T, D>& p) {
          const T r = p.distance();
          // No slip by the mirror velocity v_w = -v_i (SPHinXsys' ViscousForce with a wall:
          // 2 (v_i - v_w,average)): the zero-velocity surface lies at the wall's face, between the
          // fluid's first layer and the wall's; with v_w = 0 it lay about 0.7 dx inside the wall
          // (Poiseuille flow: 14 % too fast at 20 particles across).
          // A moving wall's mirror velocity is 2 v_w - v_i (moving_walls.hpp).
          const Vec<T, D> v_rel = moving_walls ? Vec<T, D>(v_i - wall_velocity[w]) : v_i;
          sum += v_rel * (T(2) * kernel.derivative(r) * wall_volume / (r + regularisation));
        });
        a += sum * (T(2) * viscosity / density[i]);
      }
      prior_acceleration[i] = a;
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");

  Kernel make_kernel(KernelContext& c) {
    return {inner_.search(c),      contact_.search(c),      c.read(fluid_.velocity),
            wall_.velocity_view(c), c.read(fluid_.density), c.read(fluid_.mass),
            c.write(fluid_.prior_acceleration), kernel_, gravity_, viscosity_, wall_volume_, wall_.moving()};
  }
  Index size() const { return fluid_.size(); }

 private:
  FluidVariables<T, D>& fluid_;
  WallVariables<T, D>& wall_;
  InnerRelation<T, D>& inner_;
  ContactRelation<T, D>& contact_;
  WendlandC2Kernel<T, D> kernel_;
  Vec<T, D> gravity_;
  T viscosity_;
  T wall_volume_;
};

}  // namespace unisph::sph
