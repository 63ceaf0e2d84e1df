#pragma once
// Particle shifting (fluid.particle_shifting): once per advection step every fluid particle moves
// down the gradient of its kernel sum, back towards an even arrangement,
//
//   dr_i = -A h^2 grad C_i,   grad C_i = sum_j V_j dW_ij e_ij  (fluid and wall neighbours),
//
// the form of Lind et al. (2012) and of SPHinXsys' transport-velocity correction (A = 0.4 there:
// 0.2 h^2 times twice the sum). On a regular lattice the sum vanishes by symmetry; where the
// particles bunch up or stretch apart it points to the crowded side.
//
// The free surface: there the kernel sum lacks the neighbours above, and grad C points into the
// water for the top layer and, weaker, for the layers below it within the kernel's reach. A
// particle whose kernel sum, or any of whose fluid neighbours' kernel sums, is below 0.9 of the
// lattice's lies in the band along the surface (about one cutoff deep): there only the part of
// dr_i across grad C_i is kept, so that no particle is pushed out of the water or up into the top
// layer (Lind et al. remove the normal part over such a band). So two passes: the kernel sums
// (ShiftingKernelSum, read by the neighbours, ghosts and images too), then the shifts.
// |dr_i| is capped at 0.1 h. The other variables are not re-interpolated to the new positions
// (as SPHinXsys' correction): the density is summed anew right after, and the shift is small.
// A particle's neighbours are read through the records (neighbor_records.hpp: x_j and V_j),
// which the ghosts of other ranks and the periodic images carry as their sources have them: the
// shift is the same on any number of ranks.
//
// Why: with the pair geometry taken fresh at every acoustic step (the direct search, the GPU's
// default) a standing wave lost about 5.5 % of its amplitude per period at any resolution, and the
// flumes 3 to 8 % of their height per wavelength; the arrangement drifting away from the lattice
// carried it (docs/validation.md, "The whole flumes with the correction on the GPU"). With the
// normal part removed from the top layer alone, the layer below was pushed up into it and a
// flume's surface turned noisy (docs/validation.md, "Particle shifting").
#include <cmath>
#include <type_traits>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/neighbor/contact_relation.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/sph/neighbor_records.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"

namespace unisph::sph {

// The first pass: every fluid particle's kernel sum C_i = sum_j V_j W_ij (itself, fluid and wall
// neighbours) as a fraction of the lattice's, into `kernel_sum`. The second pass reads it of its
// neighbours (images and ghosts too) to find the band along the free surface.
template <class T, int D>
class ShiftingKernelSum : public InteractionDynamics<ShiftingKernelSum<T, D>> {
 public:
  ShiftingKernelSum(FluidVariables<T, D>& fluid, InnerRelation<T, D>& inner, ContactRelation<T, D>& contact,
                    WendlandC2Kernel<T, D> kernel, T dx, T wall_volume, DiscreteVariable<T>& kernel_sum)
      : fluid_(fluid), inner_(inner), contact_(contact), kernel_(kernel), wall_volume_(wall_volume),
        kernel_sum_(kernel_sum) {
    T volume = T(1);
    for (int a = 0; a < D; ++a) volume *= dx;
    lattice_sum_ = volume * kernel.lattice_sum(dx);
  }

  struct Kernel {
    NeighborSearch<T, D> inner, contact;
    View<const PositionVolume<T, D>> records;
    View<T> kernel_sum;
    WendlandC2Kernel<T, D> kernel;
    T wall_volume;
    T inverse_lattice_sum;

    UNISPH_HOST_DEVICE void interaction(Index i, Real) const {
      T sum = kernel.value(T(0)) * records[i].volume;
      inner.for_each_neighbor(i, [&](Index j, const NeighborPair<T, D>& p) {
        sum += kernel.value(p.distance()) * records[j].volume;
      });
      contact.for_each_neighbor(
          i, [&](Index, const NeighborPair<T, D>& p) { sum += kernel.value(p.distance()) * wall_volume; });
      kernel_sum[i] = sum * inverse_lattice_sum;
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");

  Kernel make_kernel(KernelContext& c) {
    return {inner_.search(c),   contact_.search(c), c.read(fluid_.neighbor_position_volume), c.write(kernel_sum_),
            kernel_,            wall_volume_,       T(1) / lattice_sum_};
  }
  Index size() const { return fluid_.size(); }  // the owned particles

 private:
  FluidVariables<T, D>& fluid_;
  InnerRelation<T, D>& inner_;
  ContactRelation<T, D>& contact_;
  WendlandC2Kernel<T, D> kernel_;
  T wall_volume_;
  DiscreteVariable<T>& kernel_sum_;
  T lattice_sum_;
};

// The second pass: the shifts, into `shift` (a particle's neighbours must all be read before any
// moves).
template <class T, int D>
class ParticleShifting : public InteractionDynamics<ParticleShifting<T, D>> {
 public:
  // Below this fraction of the lattice's kernel sum a particle is at the free surface.
  static constexpr double surface_fraction = 0.9;

  ParticleShifting(FluidVariables<T, D>& fluid, InnerRelation<T, D>& inner, ContactRelation<T, D>& contact,
                   WendlandC2Kernel<T, D> kernel, T wall_volume, T coefficient, DiscreteVariable<T>& kernel_sum)
      : fluid_(fluid), inner_(inner), contact_(contact), kernel_(kernel), wall_volume_(wall_volume),
        coefficient_(coefficient), kernel_sum_(kernel_sum) {}

  struct Kernel {
    NeighborSearch<T, D> inner, contact;
    View<const PositionVolume<T, D>> records;  // V_j = m_j / rho_j of every fluid particle, ghosts too
    View<const T> kernel_sum;                  // C_j of every fluid particle, ghosts too
    View<Vec<T, D>> shift;
    WendlandC2Kernel<T, D> kernel;
    T wall_volume;
    T scale;  // A h^2
    T limit;  // 0.1 h

    UNISPH_HOST_DEVICE void interaction(Index i, Real) const {
      Vec<T, D> gradient{};
      bool near_surface = kernel_sum[i] < T(surface_fraction);
      inner.for_each_neighbor(i, [&](Index j, const NeighborPair<T, D>& p) {
        gradient += p.direction() * (kernel.derivative(p.distance()) * records[j].volume);
        near_surface = near_surface || kernel_sum[j] < T(surface_fraction);
      });
      contact.for_each_neighbor(i, [&](Index, const NeighborPair<T, D>& p) {
        gradient += p.direction() * (kernel.derivative(p.distance()) * wall_volume);
      });
      Vec<T, D> dr = gradient * (-scale);
      if (near_surface) {
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
    return {inner_.search(c), contact_.search(c),  c.read(fluid_.neighbor_position_volume),
            c.read(kernel_sum_), c.write(shift_),  kernel_,
            wall_volume_,     coefficient_ * h * h, largest_shift()};
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
  DiscreteVariable<T>& kernel_sum_;
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
