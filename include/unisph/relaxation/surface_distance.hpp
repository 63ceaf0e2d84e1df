#pragma once
// SurfaceDistance<D>: phi of the level set probed at every particle (negative inside the body,
// the level set's convention), written for output and for the checks of a relaxed set.

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/relaxation/owned_particles.hpp"
#include "unisph/relaxation/relaxation_surface.hpp"

namespace unisph {

template <int D>
class SurfaceDistance : public UpdateDynamics<SurfaceDistance<D>> {
 public:
  SurfaceDistance(DiscreteVariable<Vec<Real, D>>& position, DiscreteVariable<Real>& phi)
      : position_(position), phi_(phi) {}
  void set_surface(const RelaxationSurface<D>& surface) {
    surface_ = surface;
    this->invalidate_kernels();
  }
  struct Kernel {
    View<const Vec<Real, D>> position;
    View<Real> phi;
    RelaxationSurface<D> surface;
    UNISPH_HOST_DEVICE void update(Index i, Real) const { phi[i] = surface.level_set.probe_phi(position[i]); }
  };
  Kernel make_kernel(KernelContext& context) { return {context.read(position_), context.write(phi_), surface_}; }
  void count_owned_of(const ParticleSet& set) { owned_.count_owned_of(set); }  // periodic relaxation: not the images
  Index size() const { return owned_.count(position_.size()); }

 private:
  OwnedParticles owned_;
  DiscreteVariable<Vec<Real, D>>& position_;
  DiscreteVariable<Real>& phi_;
  RelaxationSurface<D> surface_{};
};

}  // namespace unisph
