#pragma once
// Particle shifting (fluid.particle_shifting): once per advection step every fluid particle moves
// down the gradient of its kernel sum, back towards an even arrangement,
//
//   dr_i = -A h^2 grad C_i,   grad C_i = sum_j V_j dW_ij e_ij  (fluid and wall neighbours),
//
// the form of Lind et al. (2012) and of SPHinXsys' transport-velocity correction (A = 0.4 there:
// 0.2 h^2 times twice the sum). On a regular lattice the sum vanishes by symmetry; where the
// particles bunch up or stretch apart it points to the crowded side. At the free surface the
// kernel sum lacks the neighbours above and grad C points into the water: there (C_i below 0.9
// of the lattice's) only the part of dr_i along the surface is kept, so that no particle is
// pushed out of the water or into it. |dr_i| is capped at 0.1 h. The other variables are not
// re-interpolated to the new positions (as SPHinXsys' correction): the density is summed anew
// right after, and the shift is small. A particle's neighbours are read through the records
// (neighbor_records.hpp: x_j and V_j), which the ghosts of other ranks and the periodic images
// carry as their sources have them: the shift is the same on any number of ranks.
//
// Why: with the pair geometry taken fresh at every acoustic step (the direct search, the GPU's
// default) a standing wave lost about 5.5 % of its amplitude per period at any resolution, and the
// flumes 3 to 8 % of their height per wavelength; the arrangement drifting away from the lattice
// carried it (docs/validation.md, "The whole flumes with the correction on the GPU").
#include <cmath>
#include <type_traits>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/neighbor/contact_relation.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/sph/neighbor_records.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"

namespace unisph::sph {

// The shifts, into `shift` (a particle's neighbours must all be read before any moves).
template <class T, int D>
class ParticleShifting : public InteractionDynamics<ParticleShifting<T, D>> {
 public:
  ParticleShifting(FluidVariables<T, D>& fluid, InnerRelation<T, D>& inner, ContactRelation<T, D>& contact,
                   WendlandC2Kernel<T, D> kernel, T dx, T wall_volume, T coefficient)
      : fluid_(fluid), inner_(inner), contact_(contact), kernel_(kernel), wall_volume_(wall_volume),
        coefficient_(coefficient) {
    T volume = T(1);
    for (int a = 0; a < D; ++a) volume *= dx;
    surface_sum_ = T(0.9) * volume * kernel.lattice_sum(dx);
  }

  struct Kernel {
    NeighborSearch<T, D> inner, contact;
    View<const PositionVolume<T, D>> records;  // V_j = m_j / rho_j of every fluid particle, ghosts too
    View<Vec<T, D>> shift;
    WendlandC2Kernel<T, D> kernel;
    T wall_volume;
    T scale;        // A h^2
    T limit;        // 0.1 h
    T surface_sum;  // 0.9 of the lattice's kernel sum

    UNISPH_HOST_DEVICE void interaction(Index i, Real) const {
      Vec<T, D> gradient{};
      T sum = kernel.value(T(0)) * records[i].volume;
      inner.for_each_neighbor(i, [&](Index j, const NeighborPair<T, D>& p) {
        const T volume = records[j].volume;
        gradient += p.direction() * (kernel.derivative(p.distance()) * volume);
        sum += kernel.value(p.distance()) * volume;
      });
      contact.for_each_neighbor(i, [&](Index, const NeighborPair<T, D>& p) {
        gradient += p.direction() * (kernel.derivative(p.distance()) * wall_volume);
        sum += kernel.value(p.distance()) * wall_volume;
      });
      Vec<T, D> dr = gradient * (-scale);
      if (sum < surface_sum) {
        const T g = std::sqrt(dot(gradient, gradient));
        if (g > T(0)) {
          const Vec<T, D> n = gradient * (T(1) / g);
          dr -= n * dot(dr, n);
        }
      }
      const T length = std::sqrt(dot(dr, dr));
      if (length > limit) dr *= limit / length;
      shift[i] = dr;
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");

  Kernel make_kernel(KernelContext& c) {
    shift_.resize(fluid_.size());
    const T h = kernel_.h;
    return {inner_.search(c), contact_.search(c), c.read(fluid_.neighbor_position_volume), c.write(shift_),
            kernel_,          wall_volume_,       coefficient_ * h * h,                      largest_shift(),
            surface_sum_};
  }
  Index size() const { return fluid_.size(); }  // the owned particles
  DiscreteVariable<Vec<T, D>>& shifts() { return shift_; }
  T largest_shift() const { return T(0.1) * kernel_.h; }

 private:
  FluidVariables<T, D>& fluid_;
  InnerRelation<T, D>& inner_;
  ContactRelation<T, D>& contact_;
  WendlandC2Kernel<T, D> kernel_;
  T wall_volume_;
  T coefficient_;
  T surface_sum_;
  // Not a particle variable: computed and applied within one advection step, before any sort.
  DiscreteVariable<Vec<T, D>> shift_{"ParticleShift"};
};

// x_i += dr_i.
template <class T, int D>
struct ApplyParticleShift {
  View<Vec<T, D>> position;
  View<const Vec<T, D>> shift;
  UNISPH_HOST_DEVICE void operator()(Index i) const { position[i] += shift[i]; }
};
static_assert(std::is_trivially_copyable_v<ApplyParticleShift<float, 2>>, "Kernels are copied to the device byte for byte.");

}  // namespace unisph::sph
