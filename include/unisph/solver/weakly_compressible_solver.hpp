#pragma once
// The weakly compressible SPH solver of a free-surface case (the short form's closed tank or the
// general form's bodies of any shape, case_description.hpp), with dual-criteria
// time stepping:
//
//   each advection step Dt = 0.25 h / max(U, |v|max, mu/(rho0 h)):
//     density summation with free-surface correction; prior acceleration (gravity, viscosity);
//     acoustic steps dt = 0.6 h / (c0 + |v|max) until Dt is covered, each:
//       pressure relaxation (Riemann, limiter) -> velocity, density relaxation (Riemann) -> density;
//     particle sort (cell order, every `sort_every` advection steps), cell lists and relations rebuilt.
//
// The floating type T (float or double) and the dimension D are template parameters; the
// four combinations are compiled once in the library (src/solver/). The policy is chosen at
// run time. Every member that launches kernels dispatches on it.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "unisph/comm/communicator.hpp"
#include "unisph/core/error.hpp"
#include "unisph/exec/policy.hpp"
#include "unisph/particles/body.hpp"
#include "unisph/solver/case_description.hpp"
#include "unisph/solver/tank_particles.hpp"

namespace unisph::sph {

// A run that went wrong (a non-finite value, a particle out of the domain).
class SimulationError : public Error {
 public:
  using Error::Error;
};

struct ObserverSample {
  double time = 0;
  double front = 0;  // largest x of the fluid + dx/2
  double kinetic_energy = 0;
  double potential_energy = 0;  // sum -m g.x
  double mass = 0;
  std::vector<double> probe_pressure;
  std::vector<double> probe_velocity;   // [[velocity_probe]]: D components per probe (dry: 0)
  std::vector<double> gauge_elevation;  // [[gauge]]: the free surface's level along -g (dry: bottom)
};

// Pairs the fluid's neighbour searches look at (candidates: the particles in the cells walked)
// and find within the cutoff, fluid-fluid and fluid-wall together; for benchmarks.
struct PairCounts {
  std::uint64_t candidate_pairs = 0;
  std::uint64_t neighbor_pairs = 0;
};

// A wall body of the case: its name and how many wall particles it has (the wall's particle ids
// are the first body's, then the second's, ...).
struct WallBodyCount {
  std::string name;
  Index count = 0;
};

// One wall body's load (report.loads): the force (D components) and the moment about
// report.moment_point (one component, about z, in 2D; three in 3D), from the fluid's pressure.
struct WallLoadSample {
  std::vector<double> force, moment;
};

// What the settling stage before time 0 took (case_description.hpp, initial.settling_time).
struct SettlingReport {
  double time = 0;  // simulated
  std::uint64_t advection_steps = 0;
  std::uint64_t acoustic_steps = 0;
  double seconds = 0;  // wall
};

template <class T, int D>
class WeaklyCompressibleSolver {
 public:
  static_assert(std::is_floating_point_v<T>, "The solver computes in float or double.");
  static_assert(D == 2 || D == 3, "The solver is built for 2D and 3D cases.");

  // Makes the particles and, where the case asks for it, settles them (initial.settling_time).
  // `settle` = false skips the settling: for a solver whose state a checkpoint restores next.
  WeaklyCompressibleSolver(const CaseDescription& description, PolicyKind policy, bool settle = true);
  // The same case on the ranks of `comm` (collective; docs/multi_gpu.md): every rank makes the
  // whole case and keeps the particles of its part of the domain, and each advection step
  // exchanges ghosts and migrating particles with the other ranks. Observers and loads are those
  // of the whole fluid on every rank; the counts and bodies below are this rank's. On one rank it
  // is the constructor above. Not yet on several ranks: periodic axes (refused with one line).
  WeaklyCompressibleSolver(const CaseDescription& description, PolicyKind policy, const comm::Communicator& comm,
                           bool settle = true);
  ~WeaklyCompressibleSolver();
  WeaklyCompressibleSolver(const WeaklyCompressibleSolver&) = delete;
  WeaklyCompressibleSolver& operator=(const WeaklyCompressibleSolver&) = delete;

  // One advection step (with its acoustic steps), shortened so as not to pass `until`.
  void advance(double until);
  ObserverSample observe();

  double time() const;
  std::uint64_t advection_steps() const;
  std::uint64_t acoustic_steps() const;
  const SettlingReport& settling() const;
  Index fluid_count() const;  // owned by this rank
  std::uint64_t fluid_count_all_ranks() const;  // collective on several ranks
  // Several ranks: fluid and wall particles this rank sent to others, and how often the domain
  // was cut anew (0 on one rank).
  std::uint64_t particles_migrated() const;
  std::uint64_t rebalances() const;
  // Several ranks: whether each rank made only its own particles at the start (a tank case;
  // otherwise every rank made the whole case and kept its share).
  bool made_in_shares() const;
  // This rank's set-up wall time: making the particles and the structures over them (on
  // several ranks also the transport's start, and a case made in shares' cut), then placing
  // them (filling their variables; on several ranks cutting a case made whole and keeping the
  // shares, sorting and the first halos). Settling and the first output come after.
  std::pair<double, double> setup_seconds() const;
  // Several ranks: the transport between them (host_staged, nccl, ...); empty on one rank.
  std::string transport() const;
  // Several ranks: this rank's wall time in building the migration and halo plans and in
  // exchanging particles and ghosts (packing, transport, unpacking), the device waited for at
  // each end; zeros on one rank. The acoustic steps' and the step ends' times on any number.
  struct RankTimings {
    double plan_seconds = 0;
    double exchange_seconds = 0;  // migrate + gather + refresh
    double migrate_seconds = 0;
    double gather_seconds = 0;
    double refresh_seconds = 0;
    std::uint64_t exchanges = 0;
    double acoustic_loop_seconds = 0;  // advance()'s acoustic steps, ghost refreshes included
    double acoustic_refresh_seconds = 0;  // of which: the ghost refreshes within them
    double step_end_seconds = 0;       // the ends of its advection steps: migration, sort, halo, lists
    double speed_wait_seconds = 0;     // in the reductions of the largest speed: waiting for the other ranks
    double sort_seconds = 0;           // of the step ends: the fluid's sort
    double rebuild_seconds = 0;        //   the cell lists, neighbour structures and records
    double migration_plan_seconds = 0; // of plan_seconds: the migrations' plans (the rest: the halos')
  };
  RankTimings rank_timings() const;
  // Several ranks: how the domain is cut (morton or bisection: UNISPH_DECOMPOSITION) and how well
  // it balanced the fluid over the run (max / mean of the owned fluid counts at each advection
  // step, collective), and this rank's fluid ghosts per advection step on average.
  struct RankBalance {
    std::string method;
    double mean_imbalance = 0;
    double worst_imbalance = 0;
    double mean_fluid_ghosts = 0;
  };
  RankBalance rank_balance() const;
  Index wall_count() const;  // the tank's wall and the obstacles'
  // Wall particles of each obstacle of the case; the wall body's particle ids are the tank's
  // first, then each obstacle's in turn.
  const std::vector<Index>& obstacle_wall_counts() const;
  // Fluid lattice points not made because they lay inside an obstacle or within dx/2 of it.
  Index removed_fluid_count() const;
  // The wall bodies: the general form's [[body]] walls, then the obstacles ("obstacle_1", ...);
  // the short form's "tank", then its obstacles.
  const std::vector<WallBodyCount>& wall_bodies() const;
  // The bodies made with fill = "relaxed" (general form), with the relaxation's final error.
  const std::vector<RelaxedBodyReport>& relaxed_bodies() const;
  // report.loads: each wall body's force and moment (about report.moment_point), in the order of
  // wall_bodies(), the mean over the acoustic steps of the last advection step (weighted by their
  // time steps); empty without report.loads or before the first step.
  const std::vector<WallLoadSample>& loads() const;
  // Fluid particles removed since the start because they left the domain (domain.leaving =
  // "remove"), and their mass.
  Index left_domain_count() const;
  double left_domain_mass() const;
  double smoothing_length() const;
  PolicyKind policy() const;
  const CaseDescription& description() const;

  Body<T, D>& fluid_body();
  Body<T, D>& wall_body();

  // Checkpoints (format: unisph/solver/solver_checkpoint.hpp). Taken between advection steps:
  // every sortable variable of fluid and wall (ids included), the time, the step counters, the
  // case, precision and dimension. `run_state` is the caller's own state (output counters...),
  // stored as an opaque block. Written to a temporary file, then renamed.
  void write_checkpoint(const std::filesystem::path& path, const std::string& run_state = {});
  // Continues from a checkpoint of the same case (its physics), precision and dimension; the
  // policy may differ. Returns the caller's run_state. Throws io::CheckpointError naming the
  // file and what is wrong. On `seq` (and `par`) the run then continues bit for bit.
  std::string restore_checkpoint(const std::filesystem::path& path);

  // For benchmarks: neighbour pairs of the current state, and one more pass of the momentum
  // (pressure-relaxation) kernel alone, waited for. The pass writes only the acceleration,
  // which the next acoustic step recomputes before using it (and, with the kernel gradient
  // correction, the correction matrices of the current positions first).
  PairCounts count_pairs();
  void pressure_relaxation_pass();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

extern template class WeaklyCompressibleSolver<float, 2>;
extern template class WeaklyCompressibleSolver<double, 2>;
extern template class WeaklyCompressibleSolver<float, 3>;
extern template class WeaklyCompressibleSolver<double, 3>;

}  // namespace unisph::sph
