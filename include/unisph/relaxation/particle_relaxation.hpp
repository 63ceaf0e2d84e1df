#pragma once
// ParticleRelaxation<D>: a body-fitted particle set made from a level set (Zhu et al. 2021):
//
//   MultiResolutionLevelSet<3> level_set(policy, shape, lo, hi, dx);          // spacing = dx
//   ParticleRelaxation<3> relaxation(policy, level_set, {lo, hi}, SeedRegion::inside, dx);
//   std::vector<RelaxationRecord> history = relaxation.run(policy, RelaxationSettings{});
//   relaxation.body().positions() ...                                          // the particles
//
// 1. Seeding: the lattice points of spacing dx in the box on the chosen side of the zero level
//    set (LatticeSeeding), volume dx^D each.
// 2. Each iteration: sort the particles into cell order, rebuild the cell list, compute the
//    residual a_i = -2 (Σ_j ∇W_ij V_j + G(x_i)) (ZeroOrderResidual, G the level set's kernel
//    gradient integral probed at x_i), move every particle and put those that crossed the
//    surface back onto it (RelaxationStep).
// 3. Stop after `iterations` or when the mean of |Σ_j ∇W_ij V_j + G| h falls below `tolerance`.
//
// The residual is minus the gradient (per unit volume) of E = Σ_i V_i (Σ_j W_ij V_j + 2 S(x_i)),
// S the missing kernel weight, provided G is exactly ∇S: the surface's probe gives both from
// one cubic Hermite interpolation (relaxation_surface.hpp), so the relaxation minimises E and a
// minimum is a state of zero residual. The cubic lattice is a saddle of E (the smallest
// eigenvalue of its Hessian is negative, docs/particle_generation.md), so the interior leaves
// the lattice for a disordered minimum; plain descent x += β a creeps there through many small
// rearrangements and stalls at a mean error of a few 1e-4 (measured), as descent does on
// glassy energies.
//
// The move (default): FIRE, the fast inertial relaxation engine of atomistic structure
// relaxation (Bitzek et al. 2006, with the FIRE 2.0 step back of Guénolé et al. 2020): the
// residual accelerates particles of unit mass, v += dt a, x += dt v, and the velocity is
// steered towards the residual, v = (1 - α) v + α |v| a / |a| (norms over all particles); while
// the power Σ a·v stays positive the time step grows by 1.1 after 5 steps, up to
// fire_largest_step h, and α shrinks by 0.99; when it turns negative every particle steps back
// half its last move and stops, the time step halves and α returns to 0.1. The time step
// starts at fire_initial_step h = 0.3 h (x moves by 0.09 h² a, below plain descent's stable
// 0.36 h²). Measured on the annulus (3760 particles): mean error 450x below the lattice's after
// 500 iterations, round-off after 1500; plain descent stays near 30x.
// The quench (fire_quench, the last 60 % of the iterations): every particle whose residual turns
// against its velocity also stops on its own. Without it, the mixing α decays to ~0 over long
// stretches of positive power, the energy the interior releases as it rearranges stays as
// vibration, and the mean error rose for 100-250 iterations at a time (sphere dx 0.05: 38x at
// 500, 161x at 600, 53x at 750, 197x at 850, 44x at 1100); with the quench from iteration 400
// it rose monotonically to 167x at 1000 (measured, docs/particle_generation.md). From the start
// it is slower (84x at 1000): the global inertia is what takes the particles off the lattice.
// The final descent (final_descent, the last 10 % of the iterations): plain descent x += β a
// instead of FIRE, β from final_descent_step h² and halved whenever the mean error rises (a fixed
// 0.25 h² or 0.1 h² blew up on teapot.stl at dx 0.28). FIRE stops with the particles still moving, and where in that motion it stops
// decides the final error: on plate_with_holes.poly (1500 iterations) the mean error of runs
// whose start differed by 1e-13 dx ranged over 3.49e-5..5.76e-5; with the final descent they end
// at 2.97e-5..2.99e-5 (measured, docs/particle_generation.md).
// Plain descent remains (fire = false): x += step a with step = min(β, largest_move h / max|a|),
// β = step_coefficient h², the cap as in SPHinXsys; the largest eigenvalue of the lattice's
// Hessian (5.6 / h²) makes it stable for β < 0.36 h², less in disordered states.
// Optional momentum (heavy ball with a per-particle restart, descent only) and a surface gap
// (SPHinXsys keeps particles dx/2 inside) are settings; both were measured worse and are off.
//
// Neighbours: direct search on every policy (the lists would be rebuilt every iteration);
// particles in cell order make it read positions contiguously and in ascending j, so every
// policy forms the same sums in the same order. With the global sums by deterministic_reduce
// (relaxation_step.hpp) and the instantiating source compiled without contraction
// (unisph_uncontracted_kernel_sources), a run has the same bits on seq, par and the GPU.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "unisph/levelset/multi_resolution_level_set.hpp"
#include "unisph/neighbor/cell_linked_list.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/neighbor/particle_sorter.hpp"
#include "unisph/neighbor/periodic_images.hpp"
#include "unisph/particles/body.hpp"
#include "unisph/relaxation/lattice_seeding.hpp"
#include "unisph/relaxation/relaxation_step.hpp"
#include "unisph/relaxation/surface_distance.hpp"
#include "unisph/relaxation/zero_order_residual.hpp"

namespace unisph {

struct RelaxationSettings {
  int iterations = 1500;              // the quench below starts at 40 % of them, the final descent at 90 %
  Real tolerance = Real(0);           // stop once the mean of |Σ ∇W V + G| h is below (0: never)
  Real step_coefficient = Real(0.25); // descent: β / h² in the linear regime (stable below 0.36)
  Real largest_move = Real(0.03125);  // descent: largest displacement per iteration, in h
  Real momentum = Real(0);            // descent: heavy-ball factor of the previous move
  Real surface_gap = Real(0);         // particles kept this far inside the surface, in dx
  bool fire = true;                   // FIRE (see move_fire); false: plain descent with step_coefficient
  Real fire_initial_step = Real(0.3); // FIRE's time step at the start, in h (x moves by dt² a)
  Real fire_largest_step = Real(0.5); // and its bound, in h
  // FIRE's quench: over this last share of `iterations`, a particle whose residual turns against
  // its velocity also stops on its own (the velocity the interior keeps is damped, see move_fire).
  Real fire_quench = Real(0.6);
  // The last share of `iterations` (with fire): plain descent x += β a, β = step_coefficient h²,
  // instead of FIRE. FIRE leaves the particles with some motion; descent lowers the energy
  // monotonically and settles them in the minimum they are near, so the final error no longer
  // depends on where in its oscillation FIRE stopped (see move()).
  Real final_descent = Real(0.1);
  Real final_descent_step = Real(0.25);  // its largest β / h² (halved when the error rises; move())
};

// One row of the history: the state before the iteration's move.
struct RelaxationRecord {
  int iteration = 0;
  Real max_error = 0;   // max over particles of |Σ_j ∇W_ij V_j + G(x_i)| h
  Real mean_error = 0;  // mean of the same
  Real step = 0;        // the step taken from this state: β (descent) or FIRE's dt (0 for the final state)
};

inline constexpr VariableTag<Real> volume_tag{"Volume"};

namespace relaxation_detail {
// A periodic relaxation's start: every seeded lattice point moved by up to `amplitude` along each
// axis, by a hash of its id (splitmix64: the same offsets on every policy). In a domain without a
// surface nothing else breaks the lattice's symmetry, and the lattice is a saddle of the energy
// that round-off alone leaves only after a few hundred to a thousand iterations (measured: the
// Taylor-Green box was still on it after 500 of 1,500).
template <int D>
struct PerturbSeeds {
  View<Vec<Real, D>> position;
  View<const std::uint64_t> id;
  Real amplitude;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    for (int a = 0; a < D; ++a) {
      std::uint64_t z = id[i] * std::uint64_t(D) + std::uint64_t(a) + 0x9E3779B97F4A7C15ull;
      z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
      z ^= z >> 31;
      const Real unit = Real(double(z >> 11) * (1.0 / 9007199254740992.0));  // [0, 1)
      position[i][a] += amplitude * (Real(2) * unit - Real(1));
    }
  }
};

struct FillVolume {
  View<Real> volume;
  Real value;
  UNISPH_HOST_DEVICE void operator()(Index i) const { volume[i] = value; }
};
}  // namespace relaxation_detail

template <int D>
class ParticleRelaxation {
 public:
  using Position = Vec<Real, D>;

  // region: inside the body, or around it within `box` (which the level set must cover).
  // The lattice points' side is the level set's sign (LevelSetSide).
  template <ExecutionPolicy P>
  ParticleRelaxation(P policy, MultiResolutionLevelSet<D>& level_set, const Box<Real, D>& box, SeedRegion region,
                     Real dx)
      : ParticleRelaxation(policy, level_set, box, region, dx,
                           LevelSetSide<D>{level_set.view(policy), region == SeedRegion::inside}) {}

  // The same with the side of the lattice points decided by `side` (e.g. WindingNumberSide, see
  // lattice_seeding.hpp), a functor in the policy's memory space.
  template <ExecutionPolicy P, class Side>
  ParticleRelaxation(P policy, MultiResolutionLevelSet<D>& level_set, const Box<Real, D>& box, SeedRegion region,
                     Real dx, const Side& side)
      : level_set_(level_set),
        region_(region),
        box_(box),
        dx_(dx),
        kernel_(WendlandC2Kernel<Real, D>::from_spacing(dx)) {
    const Real finest = level_set.finest().grid().data_spacing;
    if (std::abs(finest - dx) > Real(1e-6) * dx)
      throw Error("particle relaxation: the level set's finest spacing " + std::to_string(finest) +
                  " differs from the particle spacing " + std::to_string(dx) +
                  "; its kernel integrals use h = 1.3 times that spacing, as the particles do");
    LatticeSeeding<D, Side> seeding(Lattice<D>::covering(box, dx), side);
    const Index n = seeding.count(policy);
    if (n == 0)
      throw Error("particle relaxation: no lattice point of spacing " + std::to_string(dx) + " lies " +
                  (region == SeedRegion::inside ? "inside the body" : "outside the body within the box") +
                  "; take a smaller spacing");
    body_ = std::make_unique<Body<Real, D>>("Relaxed", box, n);
    seeding.fill(policy, body_->positions());
    ParticleSet& set = body_->particles();
    volume_ = &set.add_variable(volume_tag, sortable_output_variable);
    residual_ = &set.add_variable<Position>("Residual");
    velocity_ = &set.add_variable<Position>("RelaxationVelocity", sortable_variable);
    kernel_sum_ = &set.add_variable<Real>("KernelSum");
    distance_ = &set.add_variable<Real>("NormalDistance");
    particle_for(policy, n, relaxation_detail::FillVolume{volume_->write(policy), std::pow(dx, Real(D))});
    Box<Real, D> search_box = box;
    for (int k = 0; k < D; ++k) {
      search_box.lower[k] -= kernel_.cutoff();
      search_box.upper[k] += kernel_.cutoff();
    }
    cells_ = std::make_unique<CellLinkedList<Real, D>>(body_->positions(), search_box, kernel_.cutoff());
    inner_ = std::make_unique<InnerRelation<Real, D>>(*cells_, SearchMethod::direct);
    sorter_ = std::make_unique<ParticleSorter<Real, D>>(set, body_->positions(), cells_->grid(), 1,
                                                        SortOrder::cell_index);
    residual_method_ = std::make_unique<ZeroOrderResidual<D>>(*inner_, *volume_, *residual_, *kernel_sum_, kernel_);
    step_ = std::make_unique<RelaxationStep<D>>(body_->positions(), *velocity_, *residual_, RelaxationSettings{}.momentum);
    norms_ = std::make_unique<ResidualNorms<D>>(*residual_);
    power_ = std::make_unique<PowerAndNorms<D>>(*residual_, *velocity_);
    surface_distance_ = std::make_unique<SurfaceDistance<D>>(body_->positions(), *distance_);
  }

  // Periodic along the axes a with periodic[a] of `domain`, for particles that fill it (a fluid
  // filling a periodic box): from here on the particles wrap through those faces, see their
  // neighbours across them through images (neighbor/periodic_images.hpp: ghosts after the owned
  // particles, made anew at every measure()) and relax against no surface (the level set is not
  // probed: relax_in_shape checks that no surface lies within reach). The seeded lattice points
  // are first moved by up to 0.05 dx (PerturbSeeds), so that the relaxation leaves the lattice.
  template <ExecutionPolicy P>
  void make_periodic(P policy, const Box<Real, D>& domain, const std::array<bool, D>& periodic) {
    ParticleSet& set = body_->particles();
    particle_for(policy, set.owned_count(),
                 relaxation_detail::PerturbSeeds<D>{body_->positions().read_write(policy), set.ids().read(policy),
                                                    Real(0.05) * dx_});
    images_ = std::make_unique<PeriodicImages<Real, D>>(set, body_->positions(), domain, periodic, kernel_.cutoff());
    cells_ = std::make_unique<CellLinkedList<Real, D>>(body_->positions(), images_->search_box(), kernel_.cutoff());
    // The images follow the owned particles, out of cell order: each cell lists its particles by
    // id (an image carries its source's), so that every policy sums the neighbours in one order.
    cells_->order_within_cells_by_id(set);
    inner_ = std::make_unique<InnerRelation<Real, D>>(*cells_, SearchMethod::direct);
    sorter_ = std::make_unique<ParticleSorter<Real, D>>(set, body_->positions(), cells_->grid(), 1,
                                                        SortOrder::cell_index);
    residual_method_ = std::make_unique<ZeroOrderResidual<D>>(*inner_, *volume_, *residual_, *kernel_sum_, kernel_);
    residual_method_->count_owned_of(set);
    step_->count_owned_of(set);
    norms_->count_owned_of(set);
    power_->count_owned_of(set);
    surface_distance_->count_owned_of(set);
    surface_space_ = -1;  // the new residual method takes the surface at the next use
  }

  Body<Real, D>& body() { return *body_; }
  Index size() const { return body_->particles().owned_count(); }
  Real spacing() const { return dx_; }
  const WendlandC2Kernel<Real, D>& kernel() const { return kernel_; }
  DiscreteVariable<Position>& positions() { return body_->positions(); }
  DiscreteVariable<Real>& volumes() { return *volume_; }
  // Of the last measure(): -2 (Σ ∇W V + G) and Σ W V + S per particle.
  DiscreteVariable<Position>& residuals() { return *residual_; }
  DiscreteVariable<Real>& kernel_sums() { return *kernel_sum_; }
  // Of the last surface_distances(): phi at each particle.
  DiscreteVariable<Real>& normal_distances() { return *distance_; }

  // Sorts, rebuilds the neighbours and computes the residuals and kernel sums of the current
  // positions; returns their norms.
  template <ExecutionPolicy P>
  RelaxationRecord measure(P policy, int iteration = 0) {
    use_surface(policy);
    if (images_) images_->wrap(policy);
    sorter_->sort(policy);
    if (images_) {
      images_->build(policy);
      images_->refresh(policy, *volume_);
      inner_->set_source_count(size());
    }
    cells_->build(policy);
    inner_->update(policy);
    residual_method_->exec(policy);
    const Vec<Real, 2> norms = norms_->exec(policy);
    const Real to_error = kernel_.h / Real(2);  // |a| = 2 |g|; the error is |g| h
    return {iteration, norms[0] * to_error, norms[1] / Real(size()) * to_error, Real(0)};
  }

  // Moves the particles from the state `measured` describes (the last measure()); returns the
  // step taken.
  template <ExecutionPolicy P>
  Real move(P policy, const RelaxationSettings& settings, const RelaxationRecord& measured) {
    if (settings.surface_gap * dx_ != gap_) {
      gap_ = settings.surface_gap * dx_;
      surface_space_ = -1;
    }
    use_surface(policy);
    const Real h = kernel_.h;
    const Real largest = measured.max_error * Real(2) / h;  // max |a|
    const int descent_from = settings.iterations - int(settings.final_descent * Real(settings.iterations));
    const bool final_descent = settings.fire && settings.final_descent > Real(0) && measured.iteration >= descent_from;
    if (settings.fire && !final_descent) return move_fire(policy, settings, measured.iteration);
    Real step = settings.step_coefficient * h * h;
    if (final_descent) {
      // β starts at final_descent_step h² and halves whenever the mean error rose since the last
      // step (a stiffer spot than the lattice's makes a fixed β unstable: measured on teapot.stl),
      // growing back by 5 % a step while it falls.
      if (descent_step_ <= Real(0)) descent_step_ = settings.final_descent_step * h * h;
      else if (measured.mean_error > descent_error_) descent_step_ *= Real(0.5);
      else descent_step_ = std::min(descent_step_ * Real(1.05), settings.final_descent_step * h * h);
      descent_error_ = measured.mean_error;
      step = descent_step_;
    }
    if (largest * step > settings.largest_move * h) step = settings.largest_move * h / largest;
    if (settings.momentum != step_->momentum()) step_->set_momentum(settings.momentum);
    step_->set_descent();
    step_->exec(policy, step);
    return step;
  }

  // FIRE: the residual as a force on particles of unit mass, the velocity steered towards it
  // while the power Σ a·v stays positive, the time step raised after 5 such steps; stopped
  // (v = 0, time step halved, mixing reset) when the power turns negative.
  template <ExecutionPolicy P>
  Real move_fire(P policy, const RelaxationSettings& settings, int iteration = 0) {
    const Real h = kernel_.h;
    if (fire_step_ <= Real(0)) {
      fire_step_ = settings.fire_initial_step * h;
      fire_mixing_ = Real(0.1);
      fire_positive_ = 0;
    }
    const Real largest_step = settings.fire_largest_step * h;
    const Vec<Real, 3> p = power_->exec(policy);
    bool restart = false;
    Real steer = Real(0);
    if (p[0] > Real(0)) {
      steer = p[1] > Real(0) ? fire_mixing_ * std::sqrt(p[2] / p[1]) : Real(0);
      if (++fire_positive_ > 5) {
        fire_step_ = std::min(fire_step_ * Real(1.1), largest_step);
        fire_mixing_ *= Real(0.99);
      }
    } else {
      restart = true;
      fire_step_ *= Real(0.5);
      fire_mixing_ = Real(0.1);
      fire_positive_ = 0;
    }
    const bool quench =
        Real(iteration) >= Real(settings.iterations) * (Real(1) - settings.fire_quench) && settings.fire_quench > Real(0);
    step_->set_fire(fire_mixing_, steer, restart, quench);
    step_->exec(policy, fire_step_);
    return fire_step_;
  }

  // measure + move until `iterations` or the tolerance; the history ends with the final state.
  // progress(record) is called after every iteration (host side; may print).
  template <ExecutionPolicy P>
  std::vector<RelaxationRecord> run(P policy, const RelaxationSettings& settings,
                                    const std::function<void(const RelaxationRecord&)>& progress = {}) {
    std::vector<RelaxationRecord> history;
    for (int k = 0; k < settings.iterations; ++k) {
      RelaxationRecord r = measure(policy, k);
      if (settings.tolerance > Real(0) && r.mean_error < settings.tolerance) {
        history.push_back(r);
        if (progress) progress(r);
        return history;
      }
      r.step = move(policy, settings, r);
      history.push_back(r);
      if (progress) progress(r);
    }
    history.push_back(measure(policy, settings.iterations));
    if (progress) progress(history.back());
    return history;
  }

  // phi at every particle into normal_distances().
  template <ExecutionPolicy P>
  void surface_distances(P policy) {
    use_surface(policy);
    surface_distance_->exec(policy);
  }

 private:
  // The surface's level-set view lives in one memory space: switch it when the policy does.
  template <ExecutionPolicy P>
  void use_surface(P policy) {
    if (surface_space_ == int(P::space)) return;
    RelaxationSurface<D> surface{level_set_.view(policy), region_ == SeedRegion::inside, box_,
                                 HalfSpaceKernelIntegral<D>{kernel_}, gap_, images_ != nullptr};
    residual_method_->set_surface(surface);
    step_->set_surface(surface);
    surface_distance_->set_surface(surface);
    surface_space_ = int(P::space);
  }

  MultiResolutionLevelSet<D>& level_set_;
  SeedRegion region_;
  Box<Real, D> box_;
  Real dx_;
  WendlandC2Kernel<Real, D> kernel_;
  std::unique_ptr<Body<Real, D>> body_;
  DiscreteVariable<Real>* volume_ = nullptr;
  DiscreteVariable<Position>* residual_ = nullptr;
  DiscreteVariable<Position>* velocity_ = nullptr;
  DiscreteVariable<Real>* kernel_sum_ = nullptr;
  DiscreteVariable<Real>* distance_ = nullptr;
  std::unique_ptr<PeriodicImages<Real, D>> images_;  // make_periodic
  std::unique_ptr<CellLinkedList<Real, D>> cells_;
  std::unique_ptr<InnerRelation<Real, D>> inner_;
  std::unique_ptr<ParticleSorter<Real, D>> sorter_;
  std::unique_ptr<ZeroOrderResidual<D>> residual_method_;
  std::unique_ptr<RelaxationStep<D>> step_;
  std::unique_ptr<ResidualNorms<D>> norms_;
  std::unique_ptr<PowerAndNorms<D>> power_;
  Real fire_step_ = Real(0), fire_mixing_ = Real(0);
  Real descent_step_ = Real(0), descent_error_ = Real(0);
  int fire_positive_ = 0;
  std::unique_ptr<SurfaceDistance<D>> surface_distance_;
  int surface_space_ = -1;
  Real gap_ = Real(0);
};

}  // namespace unisph
