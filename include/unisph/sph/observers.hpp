#pragma once
// The observers of a fluid body that the solver samples after every advection step, as one
// reduction over the fluid particles (FluidObservers):
//   front            the largest coordinate along an axis, plus dx/2 (the particle's half
//                    width: a column of n particles has its front at n dx)
//   energies         kinetic sum m v^2/2 and potential sum -m g.x
//   mass             sum m, to check that it is conserved
//   pressure probes  kernel-averaged (Shepard) pressure at a point: sum p_j W V_j / sum W V_j,
//                    zero where no particle is near (a free surface)
#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/exec/reduce_ops.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"

namespace unisph::sph {

// The front, the energies, the mass and up to probes_per_pass pressure probes in one pass (more
// probes take a further pass each probes_per_pass, without the rest). As separate reductions
// each read the positions: 12 passes per advection step in the 3D dam break with its 8 probes,
// about 0.45 ms on an H100 (ncu, docs/sph.md). A component of the combined value is combined as it
// would be alone, so on seq each figure has the bits of its separate reduction.
// A probe near a periodic face reads the images across it (the caller refreshes their pressure,
// density and mass); on several ranks each rank sums its owned particles (the nearest periodic
// image of each: `period`) and the caller adds the ranks' sums.
template <class T, int D>
class FluidObservers : public KernelShell<FluidObservers<T, D>> {
 public:
  static constexpr int probes_per_pass = 4;

  struct Totals {
    T front;            // the largest coordinate along the axis (exec adds dx/2)
    Vec<T, 2> energy;   // kinetic, potential
    T mass;
    Vec<T, 2> probe[probes_per_pass];  // sum p W V, sum W V
  };
  static_assert(std::is_trivially_copyable_v<Totals>, "Totals move between threads and devices byte for byte.");

  struct Combine {
    UNISPH_HOST_DEVICE Totals operator()(const Totals& a, const Totals& b) const {
      Totals t;
      t.front = a.front < b.front ? b.front : a.front;
      t.energy = a.energy + b.energy;
      t.mass = a.mass + b.mass;
      for (int k = 0; k < probes_per_pass; ++k) t.probe[k] = a.probe[k] + b.probe[k];
      return t;
    }
  };
  UNISPH_HOST_DEVICE static Totals identity() {
    Totals t;
    t.front = Max<T>::identity();
    t.energy = Vec<T, 2>{};
    t.mass = T(0);
    for (int k = 0; k < probes_per_pass; ++k) t.probe[k] = Vec<T, 2>{};
    return t;
  }

  struct Probe {
    Vec<T, D> point;
    WendlandC2Kernel<T, D> kernel;
  };

  struct Kernel {
    View<const Vec<T, D>> position, velocity;
    View<const T> pressure, density, mass;
    Vec<T, D> gravity;
    int axis;
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");

  // One pass: particles [0, owned) give the front, energies and mass (owned = 0: probes only);
  // particles [0, n) the probes, n > owned where they read the periodic images.
  struct Launch {
    Kernel k;
    Index owned;
    int probes;
    Probe probe[probes_per_pass];
    Vec<T, D> period;  // the nearest image of an owned particle (several ranks)
    UNISPH_HOST_DEVICE Totals operator()(Index i) const {
      Totals t = identity();
      const Vec<T, D> x = k.position[i];
      if (i < owned) {
        const T m = k.mass[i];
        t.front = x[k.axis];
        t.energy = Vec<T, 2>{{T(0.5) * m * squared_norm(k.velocity[i]), -m * dot(k.gravity, x)}};
        t.mass = m;
      }
      for (int p = 0; p < probes_per_pass; ++p) {
        if (p >= probes) break;
        Vec<T, D> r = probe[p].point - x;
        for (int a = 0; a < D; ++a) {
          if (!(period[a] > T(0))) continue;
          if (r[a] > period[a] / T(2)) r[a] -= period[a];
          else if (r[a] < -period[a] / T(2)) r[a] += period[a];
        }
        const T r2 = squared_norm(r);
        const T cutoff = probe[p].kernel.cutoff();
        if (r2 >= cutoff * cutoff) continue;
        const T weight = probe[p].kernel.value(std::sqrt(r2)) * k.mass[i] / k.density[i];
        t.probe[p] = Vec<T, 2>{{k.pressure[i] * weight, weight}};
      }
      return t;
    }
  };

  // What one sample gives: the front (plus dx/2), the energies, the mass, and each probe's two
  // sums (its pressure is sum p W V / sum W V, zero where no particle is near).
  struct Sample {
    T front;
    Vec<T, 2> energy;
    T mass;
    std::vector<Vec<T, 2>> probe_sums;
  };

  // `ghosts_are_images`: ghosts are periodic images, which the probes read; false where they are
  // copies of other ranks' particles, which those ranks count (then `period`, 0 along the axes
  // that are not periodic, gives each owned particle's nearest image). `fixed_order`:
  // deterministic_reduce, the same bits on every policy (several ranks), else particle_reduce.
  FluidObservers(FluidVariables<T, D>& fluid, Vec<T, D> gravity, int axis, T dx, bool ghosts_are_images = true,
                 Vec<T, D> period = Vec<T, D>{}, bool fixed_order = false)
      : fluid_(fluid),
        gravity_(gravity),
        axis_(axis),
        half_dx_(T(0.5) * dx),
        period_(period),
        ghosts_are_images_(ghosts_are_images),
        fixed_order_(fixed_order) {}

  void add_probe(Vec<T, D> point, WendlandC2Kernel<T, D> kernel) { probes_.push_back(Probe{point, kernel}); }
  std::size_t probe_count() const { return probes_.size(); }

  Kernel make_kernel(KernelContext& c) {
    return {c.read(fluid_.position), c.read(fluid_.velocity), c.read(fluid_.pressure), c.read(fluid_.density),
            c.read(fluid_.mass),     gravity_,                axis_};
  }

  template <ExecutionPolicy P>
  Sample exec(P policy) {
    const Kernel& k = this->kernel(policy);
    const Index owned = fluid_.size();
    const Index probed = ghosts_are_images_ ? fluid_.total_size() : owned;
    Sample sample{};
    const std::size_t passes = std::max<std::size_t>(1, (probes_.size() + probes_per_pass - 1) / probes_per_pass);
    for (std::size_t pass = 0; pass < passes; ++pass) {
      Launch launch{k, pass == 0 ? owned : Index(0), 0, {}, ghosts_are_images_ ? Vec<T, D>{} : period_};
      for (std::size_t q = pass * probes_per_pass; q < probes_.size() && launch.probes < probes_per_pass; ++q)
        launch.probe[launch.probes++] = probes_[q];
      const Index n = launch.probes > 0 ? std::max(probed, launch.owned) : launch.owned;
      const Totals t = fixed_order_ ? deterministic_reduce(policy, n, identity(), Combine{}, launch)
                                    : particle_reduce(policy, n, identity(), Combine{}, launch);
      if (pass == 0) {
        sample.front = t.front + half_dx_;
        sample.energy = t.energy;
        sample.mass = t.mass;
      }
      for (int p = 0; p < launch.probes; ++p) sample.probe_sums.push_back(t.probe[p]);
    }
    return sample;
  }

 private:
  FluidVariables<T, D>& fluid_;
  Vec<T, D> gravity_;
  int axis_;
  T half_dx_;
  Vec<T, D> period_;
  bool ghosts_are_images_;
  bool fixed_order_;
  std::vector<Probe> probes_;
};

}  // namespace unisph::sph
