#pragma once
// The first half of an acoustic step (momentum), in three kernels:
//
//   PressureRelaxationStart   rho += drho/dt dt/2, p = EOS(rho), x += v dt/2
//   PressureRelaxation        a_i = -(1/rho_i) sum_j 2 p*_ij dW_ij V_j e_ij
//                             (Riemann interface pressure with the dissipation limiter)
//                             + the same with each wall dummy particle w, whose pressure is
//                             extrapolated from p_i with the prior (gravity) acceleration
//                             (wall_dummy_pressure.hpp), p_w = p_i + rho_i a0_i.(x_w - x_i), and whose
//                             velocity is the mirror of v_i (u_L - u_R = -2 v_i.n_w). The extrapolation
//                             follows the whole r_iw, not only its normal part: beside a side wall the
//                             wall particles above and below i must carry the hydrostatic gradient, or
//                             the water there lacks half its vertical pressure force and slides down
//                             the wall (measured: a tank at rest then circulates).
//   VelocityUpdate            v += (a + a0) dt, x += v dt/2   (the second half's position step)
//
// The start and the velocity update also refresh the neighbour records (neighbor_records.hpp)
// that the relaxations read of each fluid neighbour j: {x_j, m_j/rho_j} and {v_j, p_j}.
//
// The acceleration is stored and applied in its own kernel because PressureRelaxation
// reads the velocities of the neighbours.
#include <type_traits>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/neighbor/contact_relation.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/sph/acoustic_riemann_solver.hpp"
#include "unisph/sph/equation_of_state.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/sph/neighbor_records.hpp"
#include "unisph/sph/wall_dummy_pressure.hpp"
#include "unisph/sph/wall_free_box.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"

namespace unisph::sph {

template <class T, int D>
class PressureRelaxationStart : public UpdateDynamics<PressureRelaxationStart<T, D>> {
 public:
  PressureRelaxationStart(FluidVariables<T, D>& fluid, WeaklyCompressibleEquationOfState<T> eos)
      : fluid_(fluid), eos_(eos) {}
  struct Kernel {
    View<Vec<T, D>> position;
    View<const Vec<T, D>> velocity;
    View<T> density, pressure;
    View<const T> density_change_rate, mass;
    WeaklyCompressibleEquationOfState<T> eos;
    NeighborRecordWriter<T, D> records;  // x, p and rho change here
    UNISPH_HOST_DEVICE void update(Index i, Real dt_real) const {
      const T half_dt = T(0.5) * T(dt_real);
      const T rho = density[i] + density_change_rate[i] * half_dt;
      density[i] = rho;
      const T p = eos.pressure(rho);
      pressure[i] = p;
      const Vec<T, D> v = velocity[i];
      Vec<T, D> x = position[i];
      x += v * half_dt;
      position[i] = x;
      records.store(i, x, v, p, mass[i], rho);
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  Kernel make_kernel(KernelContext& c) {
    return {c.read_write(fluid_.position), c.read(fluid_.velocity),
            c.read_write(fluid_.density),  c.write(fluid_.pressure),
            c.read(fluid_.density_change_rate), c.read(fluid_.mass),
            eos_,                          NeighborRecordWriter<T, D>::make(c, fluid_)};
  }
  Index size() const { return fluid_.size(); }

 private:
  FluidVariables<T, D>& fluid_;
  WeaklyCompressibleEquationOfState<T> eos_;
};

// The momentum equation's term of one wall dummy particle w for fluid particle i,
// 2 p*_iw dW_iw V_w e_iw (a_i gets -1/rho_i times the sum over fluid and wall neighbours), with
// the wall pressure p_w of wall_pressure_of() (wall_dummy_pressure.hpp) and the mirrored normal
// velocity. One function for PressureRelaxation and the wall loads (wall_load.hpp), so they cannot
// drift apart. v_i and a0_i are relative to the wall (moving_walls.hpp): v_i - v_w and a0_i - a_w.
template <class T, int D>
UNISPH_HOST_DEVICE inline Vec<T, D> wall_pressure_term(const AcousticRiemannSolver<T>& riemann, View<const T> wall_pressure,
                                                       Index w, T p_i, T rho_i, const Vec<T, D>& v_i,
                                                       const Vec<T, D>& a0_i, const Vec<T, D>& n_w,
                                                       const NeighborPair<T, D>& pair, T dW, T wall_volume) {
  const Vec<T, D>& e = pair.direction();
  const T p_w = wall_pressure_of(wall_pressure, w, p_i, rho_i, a0_i, pair.r_ij);
  const T jump = -T(2) * dot(v_i, n_w);
  return e * (riemann.twice_interface_pressure(p_i, p_w, jump) * dW * wall_volume);
}

template <class T, int D>
class PressureRelaxation : public InteractionDynamics<PressureRelaxation<T, D>> {
 public:
  PressureRelaxation(FluidVariables<T, D>& fluid, WallVariables<T, D>& wall, InnerRelation<T, D>& inner,
                     ContactRelation<T, D>& contact, WendlandC2Kernel<T, D> kernel, AcousticRiemannSolver<T> riemann,
                     T wall_volume, WallFreeBox<T, D> wall_free)
      : fluid_(fluid), wall_(wall), inner_(inner), contact_(contact), kernel_(kernel), riemann_(riemann),
        wall_volume_(wall_volume), wall_free_(wall_free) {}

  struct Kernel {
    // The occupancy of the fastest measured build on an H100 (exec/occupancy_hint.hpp): 6 blocks of
    // 256 (at most 42 registers) in float, 3 (85) in double. Session 8 (docs/sph.md): with the
    // rsqrt pair geometry, 6 against 5 took the 3D float pass from 0.88 to 0.82 ms per 10^6; 7 gave
    // 0.80 but a slower step overall.
    static constexpr int min_blocks_per_multiprocessor = sizeof(T) == 4 ? 6 : 3;
    NeighborSearch<T, D> inner, contact;
    View<const PositionVolume<T, D>> position_volume;  // of the fluid neighbours
    View<const VelocityPressure<T, D>> velocity_pressure;
    View<const Vec<T, D>> prior_acceleration, wall_normal;
    View<const Vec<T, D>> wall_velocity, wall_acceleration;  // moving walls only (else empty)
    View<const T> density;
    View<Vec<T, D>> acceleration;
    WendlandC2Kernel<T, D> kernel;
    AcousticRiemannSolver<T> riemann;
    T wall_volume;
    WallFreeBox<T, D> wall_free;  // no wall neighbour inside
    bool moving_walls;
    View<const T> wall_pressure;  // the walls' own (fluid.wall_pressure = "averaged"), else empty

    // Static walls and no list walked by runs (one rank): compiled apart (InteractionDynamics::exec).
    bool common_case() const {
      return !moving_walls && inner.targets.run_end.empty() && contact.targets.run_end.empty();
    }
    // Static walls, lists maybe walked by runs (several ranks): compiled apart for exec_items.
    bool static_case() const { return !moving_walls; }
    UNISPH_HOST_DEVICE void interaction(Index i, Real dt) const { interact<false>(i, dt); }

    // Common: static walls (the moving walls' terms left out); Runs: the walk of id-ordered lists
    // by runs compiled in.
    template <bool Common, bool Runs = !Common>
    UNISPH_HOST_DEVICE void interact(Index i, Real) const {
      const VelocityPressure<T, D> own = velocity_pressure[i];
      const Vec<T, D> v_i = own.velocity;
      const T p_i = own.pressure;
      const T rho_i = density[i];
      Vec<T, D> force{};  // sum of 2 p* dW V_j e_ij
      const PairKernelDerivative<T, D> derivative{kernel};  // dW/dr, cached in stored lists
      for_each_neighbor_record<Runs>(inner, position_volume, i, derivative,
                               [&](Index j, const PositionVolume<T, D>& r_j, const NeighborPair<T, D>& pair, T dW) {
                                 VelocityPressureRead<T, D> s_j = velocity_pressure[j];
                                 const Vec<T, D>& e = pair.direction();
                                 const T jump = -dot(v_i - s_j.velocity, e);
                                 const T weight = dW * r_j.volume;
                                 force += e * (riemann.twice_interface_pressure(p_i, s_j.pressure, jump) * weight);
                               });
      add_wall_terms<Common, Runs>(i, p_i, rho_i, v_i, force);
      acceleration[i] = force * (-T(1) / rho_i);
    }
    // Adds the wall dummy particles' terms of fluid particle i to `sum` (none inside the
    // wall-free box of a direct search); CorrectedPressureRelaxation takes them apart to apply B_i.
    // Common: static walls; Runs: the walk by runs (see interact).
    template <bool Common = false, bool Runs = !Common>
    UNISPH_HOST_DEVICE void add_wall_terms(Index i, T p_i, T rho_i, const Vec<T, D>& v_i, Vec<T, D>& sum) const {
      if (!contact.uses_stored_lists() && wall_free.contains(position_volume[i].position)) return;
      const PairKernelDerivative<T, D> derivative{kernel};
      const Vec<T, D> a0 = prior_acceleration[i];
      contact.template for_each_weighted_neighbor<Runs>(i, derivative, [&](Index w, const NeighborPair<T, D>& pair, T dW) {
        // One call on both paths, so that the general kernel does the common case's arithmetic
        // (v - 0 and a - 0 are exact). With a call in each branch, one rank (the common kernel)
        // and two (the general one) differed in the last bits on an H100 (stored lists, double),
        // as nvcc may fuse a product and a sum differently in the two.
        Vec<T, D> v_rel = v_i, a_rel = a0;  // relative to the wall (moving_walls.hpp)
        if (!Common && moving_walls) {
          v_rel -= wall_velocity[w];
          a_rel -= wall_acceleration[w];
        }
        sum += wall_pressure_term(riemann, wall_pressure, w, p_i, rho_i, v_rel, a_rel, wall_normal[w], pair, dW,
                                  wall_volume);
      });
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
            c.write(fluid_.acceleration),
            kernel_,
            riemann_,
            wall_volume_,
            wall_free_,
            wall_.moving(),
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
  WallFreeBox<T, D> wall_free_;
};

// The kernel gradient correction (fluid.kernel_gradient_correction), in two parts:
//
//   KernelCorrectionMatrices     B_i = w I + (1 - w) M_i^-1,  w = alpha / (det M_i + alpha),
//                                M_i = -sum_j V_j r_ij dW_ij e_ij e_ij^T over fluid and wall
//                                neighbours; once per advection step (as SPHinXsys' corrected
//                                configuration), then carried to periodic images and ghosts
//   CorrectedPressureRelaxation  a_i = -(1/rho_i) [ sum_j (p_i B_i + p_j B_j + d_ij) e_ij dW_ij V_j
//                                                   + B_i sum_w (the wall terms) ],
//                                d_ij the Riemann dissipation of p*_ij (2 p*_ij - p_i - p_j)
//
// With B = M^-1 the gradient of a linear pressure field is exact at every particle, at the free
// surface too, where the kernel is cut off and M_i falls to about half of its interior value
// along the surface's normal. Without it the free surface's pressure gradient is too weak there,
// and the gravity waves of the flumes and tanks ran 3.5 to 5 % too fast at every resolution from
// d/20 to d/50 (docs/validation.md, "The kernel gradient correction"). The pair term
// p_i B_i + p_j B_j is the same seen from i and from j, so the fluid's internal forces cancel and
// the walls carry the water's weight (B_i (p_i + p_j), tried first, did not conserve momentum:
// the walls of a tank at rest carried 2 to 8 % less). B_i is blended with the identity by the
// moment's determinant with SPHinXsys' alpha = 0.3: 0.76 of the inverse inside the water
// (det M_i = 0.95), 0.62 at the surface (about 0.48), and the pair form where M_i turns singular
// (a splash, a particle climbing a wall). Smaller alphas threw particles up the walls of a swaying
// tank (alpha = 0 with B_i (p_i + p_j) within three periods; 0.1 with this form after six).
template <class T, int D>
class KernelCorrectionMatrices : public InteractionDynamics<KernelCorrectionMatrices<T, D>> {
 public:
  static_assert(D == 2 || D == 3, "The kernel gradient correction inverts a 2 x 2 or 3 x 3 moment matrix.");
  KernelCorrectionMatrices(FluidVariables<T, D>& fluid, InnerRelation<T, D>& inner, ContactRelation<T, D>& contact,
                           WendlandC2Kernel<T, D> kernel, T wall_volume, WallFreeBox<T, D> wall_free,
                           DiscreteVariable<Mat<T, D>>& matrices)
      : fluid_(fluid), inner_(inner), contact_(contact), kernel_(kernel), wall_volume_(wall_volume),
        wall_free_(wall_free), matrices_(matrices) {}

  struct Kernel {
    static constexpr T alpha = T(0.3);
    NeighborSearch<T, D> inner, contact;
    View<const PositionVolume<T, D>> position_volume;  // of the fluid neighbours
    View<Mat<T, D>> matrices;
    WendlandC2Kernel<T, D> kernel;
    T wall_volume;
    WallFreeBox<T, D> wall_free;

    UNISPH_HOST_DEVICE void interaction(Index i, Real) const {
      Mat<T, D> moment{};  // M_i
      const auto add = [&](const NeighborPair<T, D>& pair, T dW, T volume) {
        const Vec<T, D>& e = pair.direction();
        const Vec<T, D> scaled = e * (-volume * pair.distance() * dW);
        for (int a = 0; a < D; ++a) moment.row[a] += scaled * e[a];
      };
      const PairKernelDerivative<T, D> derivative{kernel};
      for_each_neighbor_record(inner, position_volume, i, derivative,
                               [&](Index, const PositionVolume<T, D>& r_j, const NeighborPair<T, D>& pair, T dW) {
                                 add(pair, dW, r_j.volume);
                               });
      if (contact.uses_stored_lists() || !wall_free.contains(position_volume[i].position))
        contact.for_each_weighted_neighbor(
            i, derivative, [&](Index, const NeighborPair<T, D>& pair, T dW) { add(pair, dW, wall_volume); });
      Mat<T, D> b = Mat<T, D>::identity();
      if (const T det = determinant(moment); det > T(0)) {
        const T w = alpha / (det + alpha);
        b = inverse(moment) * (T(1) - w);
        for (int a = 0; a < D; ++a) b(a, a) += w;
      }
      matrices[i] = b;
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");

  Kernel make_kernel(KernelContext& c) {
    const PairKernelDerivative<T, D> derivative{kernel_};
    return {inner_.search(c, derivative), contact_.search(c, derivative), c.read(fluid_.neighbor_position_volume),
            c.write(matrices_),           kernel_,                        wall_volume_,
            wall_free_};
  }
  Index size() const { return fluid_.size(); }

 private:
  FluidVariables<T, D>& fluid_;
  InnerRelation<T, D>& inner_;
  ContactRelation<T, D>& contact_;
  WendlandC2Kernel<T, D> kernel_;
  T wall_volume_;
  WallFreeBox<T, D> wall_free_;
  DiscreteVariable<Mat<T, D>>& matrices_;
};

template <class T, int D>
class CorrectedPressureRelaxation : public InteractionDynamics<CorrectedPressureRelaxation<T, D>> {
  using Base = PressureRelaxation<T, D>;

 public:
  // `matrices`: B of every fluid particle, ghosts and images included (KernelCorrectionMatrices).
  CorrectedPressureRelaxation(Base& uncorrected, DiscreteVariable<Mat<T, D>>& matrices)
      : uncorrected_(uncorrected), matrices_(matrices) {}

  struct Kernel : Base::Kernel {
    // No occupancy hint: B_j's load and product add to the pair form's measured budget; not
    // timed on a GPU yet (docs/sph.md).
    static constexpr int min_blocks_per_multiprocessor = 0;
    View<const Mat<T, D>> matrices;

    // The base's common_case() holds here too; this interact (not the base's, which leaves B out)
    // is the one InteractionDynamics::exec compiles for it.
    UNISPH_HOST_DEVICE void interaction(Index i, Real dt) const { interact<false>(i, dt); }

    template <bool Common, bool Runs = !Common>
    UNISPH_HOST_DEVICE void interact(Index i, Real) const {
      const VelocityPressure<T, D> own = this->velocity_pressure[i];
      const Vec<T, D> v_i = own.velocity;
      const T p_i = own.pressure;
      const T rho_i = this->density[i];
      const Mat<T, D> b_i = matrices[i];
      Vec<T, D> force{};
      const PairKernelDerivative<T, D> derivative{this->kernel};
      for_each_neighbor_record<Runs>(this->inner, this->position_volume, i, derivative,
                               [&](Index j, const PositionVolume<T, D>& r_j, const NeighborPair<T, D>& pair, T dW) {
                                 VelocityPressureRead<T, D> s_j = this->velocity_pressure[j];
                                 const Vec<T, D>& e = pair.direction();
                                 const T jump = -dot(v_i - s_j.velocity, e);
                                 const T dissipation =
                                     this->riemann.twice_interface_pressure(p_i, s_j.pressure, jump) - p_i - s_j.pressure;
                                 const Vec<T, D> term =
                                     b_i * (e * p_i) + matrices[j] * (e * s_j.pressure) + e * dissipation;
                                 force += term * (dW * r_j.volume);
                               });
      Vec<T, D> walls{};
      this->template add_wall_terms<Common, Runs>(i, p_i, rho_i, v_i, walls);
      force += b_i * walls;
      this->acceleration[i] = force * (-T(1) / rho_i);
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");

  Kernel make_kernel(KernelContext& c) { return Kernel{uncorrected_.make_kernel(c), c.read(matrices_)}; }
  Index size() const { return uncorrected_.size(); }

 private:
  Base& uncorrected_;  // its views, kernel and Riemann solver
  DiscreteVariable<Mat<T, D>>& matrices_;
};

template <class T, int D>
class VelocityUpdate : public UpdateDynamics<VelocityUpdate<T, D>> {
 public:
  explicit VelocityUpdate(FluidVariables<T, D>& fluid) : fluid_(fluid) {}
  struct Kernel {
    View<Vec<T, D>> position, velocity;
    View<const Vec<T, D>> acceleration, prior_acceleration;
    View<const T> pressure, mass, density;
    NeighborRecordWriter<T, D> records;  // x and v change here
    UNISPH_HOST_DEVICE void update(Index i, Real dt_real) const {
      const T dt = T(dt_real);
      const Vec<T, D> v = velocity[i] + (acceleration[i] + prior_acceleration[i]) * dt;
      velocity[i] = v;
      Vec<T, D> x = position[i];
      x += v * (T(0.5) * dt);
      position[i] = x;
      records.store(i, x, v, pressure[i], mass[i], density[i]);
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  Kernel make_kernel(KernelContext& c) {
    return {c.read_write(fluid_.position),
            c.read_write(fluid_.velocity),
            c.read(fluid_.acceleration),
            c.read(fluid_.prior_acceleration),
            c.read(fluid_.pressure),
            c.read(fluid_.mass),
            c.read(fluid_.density),
            NeighborRecordWriter<T, D>::make(c, fluid_)};
  }
  Index size() const { return fluid_.size(); }

 private:
  FluidVariables<T, D>& fluid_;
};

}  // namespace unisph::sph
