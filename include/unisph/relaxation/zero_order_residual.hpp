#pragma once
// ZeroOrderResidual<D>: the relaxation residual of every particle, from its neighbours and the
// surface,
//
//   g_i = Σ_j ∇W_ij V_j + G(x_i)         zero-order consistency error (0 for a uniform set)
//   s_i = Σ_j W_ij V_j + W(0) V_i + S(x_i)  kernel sum (its lattice value for a uniform set)
//   a_i = -2 g_i                          the residual the particles move along
//
// with G and S the part of the kernel support beyond the surface (RelaxationSurface, the level
// set's kernel integrals probed at x_i). -2 g_i is the constant-pressure SPH force of Zhu et al.
// 2021: particles move from crowded to sparse regions, and away from (or towards) the surface
// until the kernel integral beyond it balances their neighbours'.
//
// Its kernel uses the inner relation's search: with the particles in cell order the neighbours
// come in ascending j on every policy, so the sums are formed in the same order everywhere.

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/relaxation/owned_particles.hpp"
#include "unisph/relaxation/relaxation_surface.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"

namespace unisph {

template <int D>
class ZeroOrderResidual : public InteractionDynamics<ZeroOrderResidual<D>> {
 public:
  using Position = Vec<Real, D>;

  ZeroOrderResidual(InnerRelation<Real, D>& inner, DiscreteVariable<Real>& volume, DiscreteVariable<Position>& residual,
                    DiscreteVariable<Real>& kernel_sum, const WendlandC2Kernel<Real, D>& kernel)
      : inner_(inner), volume_(volume), residual_(residual), kernel_sum_(kernel_sum), kernel_(kernel) {}

  // The surface holds a level-set view of one memory space: set it before each launch on
  // another policy (the kernels are rebuilt then).
  void set_surface(const RelaxationSurface<D>& surface) {
    surface_ = surface;
    this->invalidate_kernels();
  }

  struct Kernel {
    NeighborSearch<Real, D> search;
    View<const Real> volume;
    View<Position> residual;
    View<Real> kernel_sum;
    RelaxationSurface<D> surface;
    WendlandC2Kernel<Real, D> kernel;

    UNISPH_HOST_DEVICE void interaction(Index i, Real) const {
      Position gradient{};
      Real sum = kernel.value(Real(0)) * volume[i];
      search.for_each_neighbor(i, [&](Index j, const NeighborPair<Real, D>& pair) {
        const Real r = pair.distance();
        const Real vj = volume[j];
        sum += kernel.value(r) * vj;
        // ∇_i W_ij = W'(r) e_ij with e_ij = r_ij / r (r > 0 for distinct particles within the cutoff)
        if (r > Real(0)) gradient += pair.r_ij * (kernel.derivative(r) * vj / r);
      });
      const Position x = search.sources[i];
      const auto missing = surface.missing(x);
      gradient += missing.gradient;
      residual[i] = gradient * Real(-2);
      kernel_sum[i] = sum + missing.weight;
    }
  };

  Kernel make_kernel(KernelContext& context) {
    return {inner_.search(context), context.read(volume_), context.write(residual_), context.write(kernel_sum_),
            surface_, kernel_};
  }
  void count_owned_of(const ParticleSet& set) { owned_.count_owned_of(set); }  // periodic relaxation: not the images
  Index size() const { return owned_.count(volume_.size()); }

 private:
  OwnedParticles owned_;
  InnerRelation<Real, D>& inner_;
  DiscreteVariable<Real>& volume_;
  DiscreteVariable<Position>& residual_;
  DiscreteVariable<Real>& kernel_sum_;
  WendlandC2Kernel<Real, D> kernel_;
  RelaxationSurface<D> surface_{};
};

}  // namespace unisph
