#pragma once
// The second half of an acoustic step (continuity), in two kernels:
//
//   DensityRelaxation   drho_i/dt = rho_i sum_j [ (v_i - v_j).e_ij + k (p_i - p_j)/(rho0 c0) ] dW_ij V_j
//                                 + rho_i sum_w [ 2 (v_i . n_w)(n_w . e_iw) + k (p_i - p_w)/(rho0 c0) ] dW_iw V_w
//                       (fluid.wall_continuity = "kernel_sum": (v_i - v_w).e_iw in place of the
//                       mirror's 2 (v_i . n_w)(n_w . e_iw), see WallContinuity)
//                       i.e. 2 rho_i (v_i - u*) . grad W with the acoustic Riemann interface
//                       velocity u* = (u_L + u_R)/2 + (p_L - p_R)/(2 rho0 c0), not limited (as in
//                       SPHinXsys' Riemann pressure relaxation); the wall is a mirror (normal velocity
//                       reversed, wall at rest) whose pressure p_w is the hydrostatic extrapolation
//                       of the momentum equation (wall_dummy_pressure.hpp). k = 1 keeps the velocity
//                       dissipation (fluid.continuity_dissipation = true, what the cases use), k = 0
//                       drops it. The wall term matters: without it, p_i - p_j does not cancel next
//                       to a wall under gravity (the fluid neighbours above i have a lower pressure,
//                       nothing below balances them) and the term compresses water at rest.
//                       + D_i, the density diffusion of delta-SPH where the case asks for it
//                       (density_diffusion.hpp; off by default).
//   DensityUpdate       rho += drho/dt dt/2 (the other half is applied at the next step's start)
#include <type_traits>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/neighbor/contact_relation.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/sph/acoustic_riemann_solver.hpp"
#include "unisph/sph/density_diffusion.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/sph/neighbor_records.hpp"
#include "unisph/sph/wall_dummy_pressure.hpp"
#include "unisph/sph/wall_free_box.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"

namespace unisph::sph {

// The velocity part of a wall dummy particle's term in the continuity equation.
//   mirror       2 ((v_i - v_w).n_w)(n_w.e_iw): the wall as the mirror image of the fluid (the
//                default). Twice the rate at which the fluid particle's kernel sum over the wall
//                particles changes as it approaches or leaves the wall.
//   kernel_sum   (v_i - v_w).e_iw: that rate itself, the time derivative of the wall particles'
//                share of the summed density. Where the density is summed at every advection step
//                (fluid.density_method = "summation"), the mirror compresses a particle that
//                approaches the wall twice as fast within the step as the next summation
//                does, and stretches one that leaves it twice as fast: on the dam break the wall
//                pressure moved down the wall by an amount that grew with c0 times the advection
//                step, while the wall's force did not change (docs/validation.md, "The
//                continuity equation's wall term").
enum class WallContinuity { mirror, kernel_sum };

template <class T, int D>
class DensityRelaxation : public InteractionDynamics<DensityRelaxation<T, D>> {
 public:
  DensityRelaxation(FluidVariables<T, D>& fluid, WallVariables<T, D>& wall, InnerRelation<T, D>& inner,
                    ContactRelation<T, D>& contact, WendlandC2Kernel<T, D> kernel, AcousticRiemannSolver<T> riemann,
                    T wall_volume, bool riemann_dissipation, WallFreeBox<T, D> wall_free,
                    DensityDiffusion<T, D> diffusion = {}, WallContinuity wall_continuity = WallContinuity::mirror)
      : fluid_(fluid), wall_(wall), inner_(inner), contact_(contact), kernel_(kernel), riemann_(riemann),
        wall_volume_(wall_volume), dissipation_(riemann_dissipation ? T(1) : T(0)), wall_free_(wall_free),
        diffusion_(diffusion), wall_kernel_sum_(wall_continuity == WallContinuity::kernel_sum) {}

  struct Kernel {
    // As the pressure relaxation's (exec/occupancy_hint.hpp): 6 blocks of 256 (at most 42
    // registers) in float, 3 (85) in double; measured in session 8 against 4 and 5 (docs/sph.md).
    static constexpr int min_blocks_per_multiprocessor = sizeof(T) == 4 ? 6 : 3;
    NeighborSearch<T, D> inner, contact;
    View<const PositionVolume<T, D>> position_volume;  // of the fluid neighbours
    View<const VelocityPressure<T, D>> velocity_pressure;
    View<const Vec<T, D>> prior_acceleration, wall_normal;
    View<const Vec<T, D>> wall_velocity, wall_acceleration;  // moving walls only (else empty)
    View<const T> density;
    View<T> density_change_rate;
    WendlandC2Kernel<T, D> kernel;
    AcousticRiemannSolver<T> riemann;
    T wall_volume;
    T dissipation;  // k
    WallFreeBox<T, D> wall_free;  // no wall neighbour inside
    bool moving_walls;
    DensityDiffusion<T, D> diffusion;
    bool wall_kernel_sum;  // WallContinuity::kernel_sum
    View<const T> wall_pressure;  // the walls' own (fluid.wall_pressure = "averaged"), else empty

    // Static walls, no list walked by runs (one rank) and no diffusion term: compiled apart
    // (InteractionDynamics::exec).
    bool common_case() const {
      return !moving_walls && inner.targets.run_end.empty() && contact.targets.run_end.empty() && !diffusion.on();
    }
    // The same with lists maybe walked by runs (several ranks): compiled apart for exec_items.
    bool static_case() const { return !moving_walls && !diffusion.on(); }
    UNISPH_HOST_DEVICE void interaction(Index i, Real dt) const { interact<false>(i, dt); }

    // Common: static walls and no diffusion term; Runs: the walk of id-ordered lists by runs.
    template <bool Common, bool Runs = !Common>
    UNISPH_HOST_DEVICE void interact(Index i, Real) const {
      const VelocityPressure<T, D> own = velocity_pressure[i];
      const Vec<T, D> v_i = own.velocity;
      const T p_i = own.pressure;
      T rate = T(0), diffused = T(0);
      const PairKernelDerivative<T, D> derivative{kernel};  // dW/dr, cached in stored lists
      const bool diffuse = !Common && diffusion.on();
      for_each_neighbor_record<Runs>(inner, position_volume, i, derivative,
                               [&](Index j, const PositionVolume<T, D>& r_j, const NeighborPair<T, D>& pair, T dW) {
                                 VelocityPressureRead<T, D> s_j = velocity_pressure[j];
                                 const Vec<T, D>& e = pair.direction();
                                 const T divergence = dot(v_i - s_j.velocity, e) +
                                                      dissipation * riemann.velocity_dissipation(p_i, s_j.pressure);
                                 rate += divergence * dW * r_j.volume;
                                 if (diffuse) diffused += diffusion.pair_term(p_i, s_j.pressure, pair, dW, r_j.volume);
                               });
      const T rho_i = density[i];
      if (contact.uses_stored_lists() || !wall_free.contains(position_volume[i].position)) {
        const Vec<T, D> a0 = prior_acceleration[i];
        contact.template for_each_weighted_neighbor<Runs>(i, derivative, [&](Index w, const NeighborPair<T, D>& pair, T dW) {
          const Vec<T, D>& e = pair.direction();
          const Vec<T, D> n = wall_normal[w];
          Vec<T, D> v_rel = v_i, a_rel = a0;  // relative to the wall (moving_walls.hpp)
          if (!Common && moving_walls) {
            v_rel -= wall_velocity[w];
            a_rel -= wall_acceleration[w];
          }
          const T p_w = wall_pressure_of(wall_pressure, w, p_i, rho_i, a_rel, pair.r_ij);
          const T approach = wall_kernel_sum ? dot(v_rel, e) : T(2) * dot(v_rel, n) * dot(n, e);
          const T divergence = approach + dissipation * riemann.velocity_dissipation(p_i, p_w);
          rate += divergence * dW * wall_volume;
        });
      }
      density_change_rate[i] = Common ? rate * rho_i : rate * rho_i + diffusion.coefficient * diffused;
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");

  Kernel make_kernel(KernelContext& c) {
    const PairKernelDerivative<T, D> derivative{kernel_};
    return {inner_.search(c, derivative),
            contact_.search(c, derivative),
            c.read(fluid_.neighbor_position_volume),
            c.read(fluid_.neighbor_velocity_pressure),
            c.read(fluid_.prior_acceleration),
            c.read(wall_.normal),
            wall_.velocity_view(c),
            wall_.acceleration_view(c),
            c.read(fluid_.density),
            c.write(fluid_.density_change_rate),
            kernel_,
            riemann_,
            wall_volume_,
            dissipation_,
            wall_free_,
            wall_.moving(),
            diffusion_,
            wall_kernel_sum_,
            wall_.pressure_view(c)};
  }
  Index size() const { return fluid_.size(); }
  // The box where no fluid particle has a wall neighbour (set again where walls move).
  void set_wall_free(const WallFreeBox<T, D>& box) { wall_free_ = box; }

 private:
  FluidVariables<T, D>& fluid_;
  WallVariables<T, D>& wall_;
  InnerRelation<T, D>& inner_;
  ContactRelation<T, D>& contact_;
  WendlandC2Kernel<T, D> kernel_;
  AcousticRiemannSolver<T> riemann_;
  T wall_volume_;
  T dissipation_;
  WallFreeBox<T, D> wall_free_;
  DensityDiffusion<T, D> diffusion_;
  bool wall_kernel_sum_;
};

template <class T, int D>
class DensityUpdate : public UpdateDynamics<DensityUpdate<T, D>> {
 public:
  explicit DensityUpdate(FluidVariables<T, D>& fluid) : fluid_(fluid) {}
  struct Kernel {
    View<T> density;
    View<const T> density_change_rate;
    UNISPH_HOST_DEVICE void update(Index i, Real dt) const { density[i] += density_change_rate[i] * (T(0.5) * T(dt)); }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  Kernel make_kernel(KernelContext& c) { return {c.read_write(fluid_.density), c.read(fluid_.density_change_rate)}; }
  Index size() const { return fluid_.size(); }

 private:
  FluidVariables<T, D>& fluid_;
};

}  // namespace unisph::sph
