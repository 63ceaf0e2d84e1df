#pragma once
// Density by kernel summation with the free-surface correction, once per advection step.
//
//   rho_sum,i = ( sum_j m_j W_ij  +  m_i (V_wall / V_i0) sum_wall W_iw ) / (V_i0 sigma0)
//
// sigma0 is the lattice sum of W (WendlandC2Kernel::lattice_sum), V_i0 = dx^D, so a particle
// inside a fluid at rest on the initial lattice gets exactly its initial density. Wall dummy
// particles count as fluid of particle i's own density (they are its mirror). Near a free
// surface the sum lacks neighbours and underestimates the density. The correction, in one of
// two forms (fluid.free_surface_density), both of SPHinXsys' lineage:
//   "reference": rho_i <- max(rho_sum, rho0): the reference density where the sum falls short
//                (zero pressure, no tension); SPHinXsys' form since about 2023;
//   "carried":   rho_i <- rho_sum + max(0, rho_n - rho_sum) rho0 / rho_n, rho_n the density the
//                continuity equation carried: where the sum falls short of it, the shortfall is
//                added back (scaled by rho0 / rho_n); SPHinXsys' earlier form, with which its
//                regression records of the 2D dam break were made (docs/validation.md);
//   "none":      rho_i <- rho_sum: no correction, for a flow without free surface (a periodic
//                box such as the Taylor-Green vortex), where the density may fall below rho0.
// Where the sum is the larger, it replaces the carried density, so the continuity equation's
// drift does not accumulate over advection steps.
//
// Like the relaxations, the pass reads x_j from the neighbour records (neighbor_records.hpp: one
// aligned load per candidate of a direct search in cell order), which the solver keeps current
// for every owned particle, image and ghost at the start of an advection step; it skips the walk
// over the wall's cells for particles in the wall-free box (wall_free_box.hpp), and compiles its
// common case (no list walked by runs) apart. Measured on an H100 (3D dam break, dx 0.00625,
// FP32, docs/sph.md): 1.98 ms per pass, 2.27 before.
#include <type_traits>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/neighbor/contact_relation.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/sph/neighbor_records.hpp"
#include "unisph/sph/wall_free_box.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"

namespace unisph::sph {

// fluid.free_surface_density (above).
enum class SurfaceDensity { reference, carried, none };

template <class T, int D>
class DensitySummationFreeSurface : public InteractionDynamics<DensitySummationFreeSurface<T, D>> {
 public:
  DensitySummationFreeSurface(FluidVariables<T, D>& fluid, InnerRelation<T, D>& inner, ContactRelation<T, D>& wall,
                              WendlandC2Kernel<T, D> kernel, T dx, T reference_density, SurfaceDensity mode)
      : fluid_(fluid), inner_(inner), wall_(wall), kernel_(kernel), reference_density_(reference_density),
        add_back_shortfall_(mode == SurfaceDensity::carried), uncorrected_(mode == SurfaceDensity::none) {
    T volume = T(1);
    for (int a = 0; a < D; ++a) volume *= dx;
    inverse_reference_sum_ = T(1) / (volume * kernel.lattice_sum(dx));
    self_weight_ = kernel.value(T(0));
  }

  struct Kernel {
    // exec/occupancy_hint.hpp: 6 blocks of 256 (at most 42 registers) in float, 4 (64) in double.
    static constexpr int min_blocks_per_multiprocessor = sizeof(T) == 4 ? 6 : 4;
    NeighborSearch<T, D> inner, wall;
    View<const PositionVolume<T, D>> position_volume;  // x_j of the fluid neighbours
    View<const T> mass;
    View<T> density;
    WendlandC2Kernel<T, D> kernel;
    T self_weight, inverse_reference_sum, reference_density;
    bool add_back_shortfall;  // "carried" (above)
    bool uncorrected;         // "none"
    WallFreeBox<T, D> wall_free;  // no wall neighbour inside

    // No list walked by runs (one rank): compiled apart (InteractionDynamics::exec).
    bool common_case() const { return inner.targets.run_end.empty() && wall.targets.run_end.empty(); }
    UNISPH_HOST_DEVICE void interaction(Index i, Real dt) const { interact<false>(i, dt); }

    template <bool Common>
    UNISPH_HOST_DEVICE void interact(Index i, Real) const {
      const WendlandC2Kernel<T, D> w = kernel;
      const auto value = [w](const NeighborPair<T, D>& p) { return w.value(p.distance()); };
      T sum = mass[i] * self_weight;
      for_each_neighbor_record<!Common>(inner, position_volume, i, value,
                                        [&](Index j, const PositionVolume<T, D>&, const NeighborPair<T, D>&, T W) {
                                          sum += mass[j] * W;
                                        });
      T wall_sum = T(0);
      if (wall.uses_stored_lists() || !wall_free.contains(position_volume[i].position))
        wall.template for_each_weighted_neighbor<!Common>(i, value, [&](Index, const NeighborPair<T, D>&, T W) { wall_sum += W; });
      sum += mass[i] * wall_sum;  // the wall's volume is dx^D, as V_i0
      const T summed = sum * inverse_reference_sum;
      if (uncorrected) {
        density[i] = summed;
      } else if (add_back_shortfall) {
        const T carried = density[i];
        const T shortfall = carried - summed;
        density[i] = shortfall > T(0) ? summed + shortfall * (reference_density / carried) : summed;
      } else {
        density[i] = summed > reference_density ? summed : reference_density;
      }
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "The density summation kernel is copied to the device byte for byte.");

  Kernel make_kernel(KernelContext& context) {
    return {inner_.search(context),
            wall_.search(context),
            context.read(fluid_.neighbor_position_volume),
            context.read(fluid_.mass),
            context.read_write(fluid_.density),
            kernel_,
            self_weight_,
            inverse_reference_sum_,
            reference_density_,
            add_back_shortfall_,
            uncorrected_,
            wall_free_};
  }
  Index size() const { return fluid_.size(); }
  // The box where no fluid particle has a wall neighbour (empty: every particle walks the wall).
  void set_wall_free(const WallFreeBox<T, D>& box) { wall_free_ = box; }

 private:
  FluidVariables<T, D>& fluid_;
  InnerRelation<T, D>& inner_;
  ContactRelation<T, D>& wall_;
  WendlandC2Kernel<T, D> kernel_;
  T reference_density_;
  bool add_back_shortfall_;
  bool uncorrected_;
  T inverse_reference_sum_ = T(1);
  T self_weight_ = T(0);
  WallFreeBox<T, D> wall_free_ = WallFreeBox<T, D>::empty();
};

}  // namespace unisph::sph
