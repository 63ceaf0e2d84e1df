#pragma once
// The force of the fluid on each wall body, and its moment about a point.
//
// For every fluid particle i, the pressure force its wall neighbours w exert on it in the
// momentum equation, exactly the wall part of PressureRelaxation (pressure_relaxation.hpp):
//   m_i a_i^w = -(m_i / rho_i) sum_w 2 p*_iw dW_iw V_w e_iw      (wall_pressure_term(), shared),
// with the same Riemann interface pressure, the same dummy pressure p_w = p_i - rho_i a0_i . r_iw
// (wall_dummy_pressure.hpp), the same dW/dr (PairKernelDerivative) and the same wall volume dx^D,
// split by the wall body of w and taken as the reaction on the wall:
//   F_b = -sum_i m_i a_i^(w in body b),
//   M_b = sum_i (x_i - c) x (-m_i a_i^(w in body b))   about the point c (a scalar, the z
//         component, in 2D). Every pair force lies along e_iw, the line through x_i and x_w, so
//         this is the moment of the pair forces applied at the wall particles as well (to
//         round-off).
//
// A wall particle's body comes from its id: the wall set's ids are the first body's (ids
// first_id .. first_id + count_0 - 1), then the second's, ... (the solver's wall_bodies()).
// Moving walls (moving_walls.hpp) enter as in PressureRelaxation: the fluid's velocity and prior
// acceleration relative to the wall's. Not included: the viscous force of the walls (PriorAcceleration's wall
// term where fluid.viscosity > 0): it is summed into the prior acceleration with the fluid's
// own viscous term and not stored apart.
//
// Two kernels: WallLoadTerms writes each fluid particle's force and moment per body (n x B
// records, WallBodyLoad), then one WallLoadSum per body sums its column with deterministic_reduce, so the
// per-particle terms being equal, the loads have the same bits on seq, par and the GPU.
// The caller keeps the contact relation (fluid -> wall) up to date (update() after the wall's
// cell list was built and whenever the fluid moved) and calls exec(policy) between steps.
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

#include "unisph/core/error.hpp"
#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/exec/reduce_ops.hpp"
#include "unisph/neighbor/contact_relation.hpp"
#include "unisph/sph/acoustic_riemann_solver.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/sph/pressure_relaxation.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"

namespace unisph::sph {

// Components of a moment: the z component in 2D, a vector in 3D.
template <int D>
inline constexpr int moment_components = D == 2 ? 1 : 3;

// The load on one wall body: force and moment (1 component in 2D, 3 in 3D).
template <class T, int D>
struct WallBodyLoad {
  Vec<T, D> force;  // no initialisers: a variable's element (value-initialise: WallBodyLoad<T, D>{})
  Vec<T, moment_components<D>> moment;
  UNISPH_HOST_DEVICE friend WallBodyLoad operator+(const WallBodyLoad& a, const WallBodyLoad& b) {
    return {a.force + b.force, a.moment + b.moment};
  }
};
template <class T, int D>
using WallLoadRecord = WallBodyLoad<T, D>;

// (x_i - c) x F: the z component in 2D.
template <class T, int D>
UNISPH_HOST_DEVICE inline Vec<T, moment_components<D>> moment_of(const Vec<T, D>& arm, const Vec<T, D>& force) {
  if constexpr (D == 2) {
    return Vec<T, 1>{{arm[0] * force[1] - arm[1] * force[0]}};
  } else {
    return cross(arm, force);
  }
}

// Each fluid particle's reaction force and moment on each wall body: record i * B + b.
template <class T, int D>
class WallLoadTerms : public InteractionDynamics<WallLoadTerms<T, D>> {
 public:
  WallLoadTerms(FluidVariables<T, D>& fluid, WallVariables<T, D>& wall, DiscreteVariable<std::uint64_t>& wall_ids,
                DiscreteVariable<std::uint64_t>& body_ends, ContactRelation<T, D>& contact,
                DiscreteVariable<WallLoadRecord<T, D>>& terms, WendlandC2Kernel<T, D> kernel,
                AcousticRiemannSolver<T> riemann, T wall_volume, Vec<T, D> moment_point)
      : fluid_(fluid), wall_(wall), wall_ids_(wall_ids), body_ends_(body_ends), contact_(contact), terms_(terms),
        kernel_(kernel), riemann_(riemann), wall_volume_(wall_volume), moment_point_(moment_point) {}

  struct Kernel {
    NeighborSearch<T, D> contact;
    View<const Vec<T, D>> position, velocity, prior_acceleration, wall_normal;
    View<const Vec<T, D>> wall_velocity, wall_acceleration;  // moving walls only (else empty)
    View<const T> density, pressure, mass;
    View<const std::uint64_t> wall_id, body_end;  // body b holds the ids below body_end[b]
    View<WallLoadRecord<T, D>> terms;
    WendlandC2Kernel<T, D> kernel;
    AcousticRiemannSolver<T> riemann;
    T wall_volume;
    Vec<T, D> moment_point;
    bool moving_walls;
    View<const Mat<T, D>> correction;  // B_i of the corrected pressure force (else empty)
    View<const T> wall_pressure;       // the walls' own (fluid.wall_pressure = "averaged"), else empty

    UNISPH_HOST_DEVICE void interaction(Index i, Real) const {
      const Index bodies = body_end.size();
      const Vec<T, D> v_i = velocity[i];
      const T p_i = pressure[i];
      const T rho_i = density[i];
      const Vec<T, D> a0 = prior_acceleration[i];
      WallLoadRecord<T, D>* own = &terms[i * bodies];
      for (Index b = 0; b < bodies; ++b) own[b] = WallLoadRecord<T, D>{};
      const PairKernelDerivative<T, D> derivative{kernel};
      // Per body, the sum of the terms PressureRelaxation adds for the same neighbours.
      contact.for_each_weighted_neighbor(i, derivative, [&](Index w, const NeighborPair<T, D>& pair, T dW) {
        const Vec<T, D> term =
            moving_walls ? wall_pressure_term(riemann, wall_pressure, w, p_i, rho_i, Vec<T, D>(v_i - wall_velocity[w]),
                                              Vec<T, D>(a0 - wall_acceleration[w]), wall_normal[w], pair, dW, wall_volume)
                         : wall_pressure_term(riemann, wall_pressure, w, p_i, rho_i, v_i, a0, wall_normal[w], pair, dW,
                                              wall_volume);
        const std::uint64_t id = wall_id[w];
        Index b = 0;
        while (b + 1 < bodies && id >= body_end[b]) ++b;
        own[b].force += term;
      });
      // The acceleration from body b is -(1/rho_i) sum; the reaction on b is -m_i times it.
      const Vec<T, D> arm = position[i] - moment_point;
      const T m_i = mass[i];
      const bool corrected = !correction.empty();
      for (Index b = 0; b < bodies; ++b) {
        const Vec<T, D> term = corrected ? Vec<T, D>(correction[i] * own[b].force) : own[b].force;
        const Vec<T, D> acceleration = term * (-T(1) / rho_i);
        const Vec<T, D> force = acceleration * (-m_i);
        own[b] = WallLoadRecord<T, D>{force, moment_of<T, D>(arm, force)};
      }
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");

  Kernel make_kernel(KernelContext& c) {
    const PairKernelDerivative<T, D> derivative{kernel_};
    return {contact_.search(c, derivative),
            c.read(fluid_.position),
            c.read(fluid_.velocity),
            c.read(fluid_.prior_acceleration),
            c.read(wall_.normal),
            wall_.velocity_view(c),
            wall_.acceleration_view(c),
            c.read(fluid_.density),
            c.read(fluid_.pressure),
            c.read(fluid_.mass),
            c.read(wall_ids_),
            c.read(body_ends_),
            c.write(terms_),
            kernel_,
            riemann_,
            wall_volume_,
            moment_point_,
            wall_.moving(),
            correction_ ? c.read(*correction_) : View<const Mat<T, D>>{},
            wall_.pressure_view(c)};
  }
  Index size() const { return fluid_.size(); }
  void use_correction(DiscreteVariable<Mat<T, D>>* correction) { correction_ = correction; }

 private:
  DiscreteVariable<Mat<T, D>>* correction_ = nullptr;
  FluidVariables<T, D>& fluid_;
  WallVariables<T, D>& wall_;
  DiscreteVariable<std::uint64_t>& wall_ids_;
  DiscreteVariable<std::uint64_t>& body_ends_;
  ContactRelation<T, D>& contact_;
  DiscreteVariable<WallLoadRecord<T, D>>& terms_;
  WendlandC2Kernel<T, D> kernel_;
  AcousticRiemannSolver<T> riemann_;
  T wall_volume_;
  Vec<T, D> moment_point_;
};

// The sum over the fluid particles of body b's column of WallLoadTerms' records, in the fixed
// association of deterministic_reduce.
template <class T, int D>
class WallLoadSum : public ReduceDynamics<WallLoadSum<T, D>, Sum<WallLoadRecord<T, D>>, ReduceOrder::fixed> {
 public:
  WallLoadSum(DiscreteVariable<WallLoadRecord<T, D>>& terms, Index bodies, Index body, const FluidVariables<T, D>& fluid)
      : terms_(terms), bodies_(bodies), body_(body), fluid_(fluid) {}
  struct Kernel {
    View<const WallLoadRecord<T, D>> terms;
    Index bodies, body;
    UNISPH_HOST_DEVICE WallLoadRecord<T, D> reduce(Index i, Real) const { return terms[i * bodies + body]; }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  Kernel make_kernel(KernelContext& c) { return {c.read(terms_), bodies_, body_}; }
  Index size() const { return fluid_.size(); }

 private:
  DiscreteVariable<WallLoadRecord<T, D>>& terms_;
  Index bodies_, body_;
  const FluidVariables<T, D>& fluid_;
};

// The loads on every wall body (the method a caller uses).
template <class T, int D>
class WallLoad {
 public:
  // body_counts: the wall particles of each body, in the order of the wall set's ids, which
  // start at first_wall_id; they must add up to the wall's particles.
  WallLoad(FluidVariables<T, D>& fluid, WallVariables<T, D>& wall, DiscreteVariable<std::uint64_t>& wall_ids,
           std::uint64_t first_wall_id, const std::vector<Index>& body_counts, ContactRelation<T, D>& contact,
           WendlandC2Kernel<T, D> kernel, AcousticRiemannSolver<T> riemann, T wall_volume, Vec<T, D> moment_point)
      : fluid_(fluid),
        body_ends_("WallLoad.BodyEnds", Index(body_counts.size())),
        terms_("WallLoad.Terms", 0),
        terms_kernel_(fluid, wall, wall_ids, body_ends_, contact, terms_, kernel, riemann, wall_volume, moment_point) {
    if (body_counts.empty()) throw Error("WallLoad: no wall body");
    std::uint64_t end = first_wall_id;
    View<std::uint64_t> ends = body_ends_.write(MemorySpace::host);
    for (std::size_t b = 0; b < body_counts.size(); ++b) ends[Index(b)] = end += body_counts[b];
    if (end - first_wall_id != std::uint64_t(wall.size()))
      throw Error("WallLoad: the wall bodies' counts add up to " + std::to_string(end - first_wall_id) +
                  " particles; the wall has " + std::to_string(wall.size()));
    for (std::size_t b = 0; b < body_counts.size(); ++b)
      sums_.push_back(std::make_unique<WallLoadSum<T, D>>(terms_, Index(body_counts.size()), Index(b), fluid));
  }

  Index bodies() const { return body_ends_.size(); }

  // With fluid.kernel_gradient_correction the fluid's wall force is B_i times the wall terms
  // (CorrectedPressureRelaxation): the loads apply each particle's B_i the same way.
  void use_correction(DiscreteVariable<Mat<T, D>>& matrices) { terms_kernel_.use_correction(&matrices); }

  // The load on each wall body, in the order of body_counts.
  template <ExecutionPolicy P>
  std::vector<WallBodyLoad<T, D>> exec(P policy) {
    const Index records = fluid_.size() * bodies();
    if (terms_.size() != records) terms_.resize(records);  // the fluid may have lost particles
    terms_kernel_.exec(policy);
    std::vector<WallBodyLoad<T, D>> loads;
    for (Index b = 0; b < bodies(); ++b) loads.push_back(sums_[b]->exec(policy));
    return loads;
  }

 private:
  FluidVariables<T, D>& fluid_;
  DiscreteVariable<std::uint64_t> body_ends_;
  DiscreteVariable<WallLoadRecord<T, D>> terms_;
  WallLoadTerms<T, D> terms_kernel_;
  std::vector<std::unique_ptr<WallLoadSum<T, D>>> sums_;
};

}  // namespace unisph::sph
