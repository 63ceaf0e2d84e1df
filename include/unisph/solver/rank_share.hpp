#pragma once
// RankShare<T, D>: what a solver on one of several ranks adds to a run on one (docs/multi_gpu.md,
// "The solver on several ranks").
//
// The domain is covered by cells at least `width` wide (comm::CellGrid), cut among the ranks
// along the Morton curve with the fluid's particles as weights (comm::decompose_morton), or by
// recursive coordinate bisection where UNISPH_DECOMPOSITION=bisection (decompose_bisection). Each
// rank owns the fluid and wall particles in its cells and holds ghost copies of the particles
// of other ranks within `width` of its cells (comm::Halo). `width` is the kernel's cutoff plus
// a skin: the halo is built once per advection step, and the acoustic steps move the particles
// within it, so a pair that comes within the cutoff during the step must have been within
// cutoff + skin at its start. The solver checks that the particles travel less than half the
// skin in a step (`travel_limit()`) and stops otherwise.
//
// Sets are made whole on every rank (the same particles and ids as on one rank) and each rank
// keeps its share (keep_owned), so that ids are global. After each advection step, migrate()
// sends the owned particles that left a rank's cells to their new owner, every sortable
// variable with them; gather() builds the halo and fills the ghosts; refresh() sends the named
// variables of the same ghosts again.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "unisph/comm/communicator.hpp"
#include "unisph/comm/decomposition.hpp"
#include "unisph/comm/exchange.hpp"
#include "unisph/comm/halo.hpp"
#include "unisph/comm/migrate.hpp"
#include "unisph/comm/transport.hpp"
#include "unisph/core/box.hpp"
#include "unisph/exec/backend/cuda/runtime.hpp"
#include "unisph/particles/body.hpp"

namespace unisph::sph {

template <class T, int D>
class RankShare {
 public:
  using PlanPosition = Vec<Real, D>;
  using Halo = comm::Halo<D, T>;

  // `periodic[a]` != 0: axis a is periodic (the halo then holds the images across its faces).
  RankShare(const comm::Communicator& comm, const Box<T, D>& domain, T cutoff, T skin, MemorySpace space,
            double rebalance_fraction, Vec<int, D> periodic = Vec<int, D>{})
      : comm_(comm),
        transport_(comm::make_transport(transport_kind(space), comm)),
        width_(cutoff + skin),
        skin_(skin),
        rebalance_fraction_(rebalance_fraction),
        method_(decomposition_method()),
        grid_(grid_of(comm, domain, cutoff, skin, periodic)) {}

  // The decomposition's cell grid: cells at least cutoff + skin wide over the domain.
  static comm::CellGrid<D> grid_of(const comm::Communicator& comm, const Box<T, D>& domain, T cutoff, T skin,
                                   Vec<int, D> periodic = Vec<int, D>{}) {
    Box<Real, D> box;
    for (int a = 0; a < D; ++a) {
      box.lower[a] = Real(domain.lower[a]);
      box.upper[a] = Real(domain.upper[a]);
    }
    const T width = cutoff + skin;
    comm::CellGrid<D> grid = comm::make_cell_grid<D>(box, Real(width), periodic);
    if (grid.cell_count() < std::uint64_t(comm.size()))
      throw Error("the domain holds " + std::to_string(grid.cell_count()) + " cells of " + std::to_string(double(width)) +
                  " (the kernel's cutoff and the halo's skin) for " + std::to_string(comm.size()) +
                  " ranks; run on at most " + std::to_string(grid.cell_count()) + " ranks");
    return grid;
  }
  // The cut of fluid positions spread over the ranks in any way (collective; each rank passes
  // its own), by the method UNISPH_DECOMPOSITION names.
  static comm::Decomposition<D> cut(const comm::Communicator& comm, const comm::CellGrid<D>& grid,
                                    std::span<const PlanPosition> x) {
    return decomposition_method() == comm::DecompositionMethod::morton ? comm::decompose_morton<D>(comm, grid, x)
                                                                       : comm::decompose_bisection<D>(comm, grid, x);
  }
  // Takes a cut made before the particles were (a case made in shares: each rank made the
  // particles of its own cells only), on this share's grid.
  void adopt(comm::Decomposition<D> cut) {
    decomposition_ = std::move(cut);
    ++decompositions_;
  }

  // The transport between ranks: UNISPH_TRANSPORT (host_staged, nccl, cuda_aware_mpi) where
  // set, else comm::default_transport (NCCL for GPU memory where the build has it).
  static comm::TransportKind transport_kind(MemorySpace space) {
    if (const char* name = std::getenv("UNISPH_TRANSPORT"); name && *name) return comm::parse_transport(name);
    return comm::default_transport(space);
  }

  // UNISPH_DECOMPOSITION (morton, bisection) where set, else morton.
  static comm::DecompositionMethod decomposition_method() {
    const char* name = std::getenv("UNISPH_DECOMPOSITION");
    if (!name || !*name || std::string(name) == "morton") return comm::DecompositionMethod::morton;
    if (std::string(name) == "bisection") return comm::DecompositionMethod::bisection;
    throw Error("UNISPH_DECOMPOSITION='" + std::string(name) + "': use morton or bisection");
  }
  comm::DecompositionMethod method() const { return method_; }

  // How well the cuts balanced the fluid: max / mean of the owned counts at each check
  // (unbalanced()), their mean and the worst.
  struct Balance {
    double mean_imbalance = 0;
    double worst_imbalance = 0;
    std::uint64_t checks = 0;
  };
  Balance balance() const {
    return {checks_ ? imbalance_sum_ / double(checks_) : 0.0, imbalance_worst_, checks_};
  }

  const comm::Communicator& comm() const { return comm_; }
  comm::Transport& transport() { return *transport_; }
  const comm::Decomposition<D>& decomposition() const { return decomposition_; }
  T width() const { return width_; }
  bool periodic() const {
    for (int a = 0; a < D; ++a)
      if (grid_.periodic[a]) return true;
    return false;
  }
  // Whether this rank owns the point (its cell's owner; outside the domain: the nearest edge
  // cell's, across a periodic face: the wrapped point's).
  bool owns(const Vec<T, D>& x) const {
    PlanPosition y;
    for (int a = 0; a < D; ++a) y[a] = Real(x[a]);
    return decomposition_.owner(y) == comm_.rank();
  }
  // The farthest a particle may move within one advection step (the halo holds the particles
  // within cutoff + skin; two particles approach by at most twice this).
  T travel_limit() const { return skin_ / T(2); }
  std::uint64_t rebalances() const { return rebalances_; }

  // Where a rank's time in the layer went (see the header comment).
  struct Timings {
    double plan_seconds = 0;      // migration and halo plans
    double migration_plan_seconds = 0;  // of which: the migrations'
    double exchange_seconds = 0;  // migrate, gather and refresh exchanges (packing included)
    double migrate_seconds = 0;   // of which: migrations (with adopt_owned)
    double gather_seconds = 0;    //   halos' first fills (every sortable variable)
    double refresh_seconds = 0;   //   refreshes of named variables
    std::uint64_t exchanges = 0;
  };
  const Timings& timings() const { return timings_; }
  // The clock after the device's queued work (so that a phase's time includes its kernels).
  template <ExecutionPolicy P>
  static std::chrono::steady_clock::time_point now(P policy) {
    fence(policy);
    return std::chrono::steady_clock::now();
  }
  static double seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  }

  // Collective: cuts the domain anew with the fluid's owned particles as weights.
  void decompose(Body<T, D>& fluid) {
    const std::vector<PlanPosition> x = plan_positions(fluid);
    adopt(cut(comm_, grid_, std::span<const PlanPosition>(x)));
  }
  // Collective: true when the owned fluid counts have drifted apart by more than the rebalance
  // fraction: max / mean above 1 + fraction, and above (1 + fraction) times what the last cut
  // reached (a cut falls on cell boundaries, so a few particles per cell may not balance
  // within the fraction; without the second condition such a run would cut again every step).
  bool unbalanced(Index owned) {
    const double now = comm::imbalance(comm_, std::uint64_t(owned));
    imbalance_sum_ += now;
    imbalance_worst_ = std::max(imbalance_worst_, now);
    ++checks_;
    if (measure_cut_) {
      reached_ = now;
      measure_cut_ = false;
    }
    return now > (1 + rebalance_fraction_) * std::max(1.0, reached_);
  }
  void count_rebalance() {
    ++rebalances_;
    measure_cut_ = true;  // the next check measures what this cut reached
  }

  // Keeps the owned particles of a set made whole on every rank: the others are dropped, the
  // kept ones stay in their order.
  template <ExecutionPolicy P>
  void keep_owned(P policy, Body<T, D>& body) {
    ParticleSet& set = body.particles();
    const std::vector<PlanPosition> x = plan_positions(body);
    std::vector<char> mine(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) mine[i] = decomposition_.owner(x[i]) == comm_.rank();
    std::vector<std::uint32_t> order;
    order.reserve(x.size());
    for (std::size_t i = 0; i < x.size(); ++i)
      if (mine[i]) order.push_back(std::uint32_t(i));
    const Index kept = order.size();
    for (std::size_t i = 0; i < x.size(); ++i)
      if (!mine[i]) order.push_back(std::uint32_t(i));
    DiscreteVariable<std::uint32_t> permutation("RankShare.Keep");
    permutation.assign(order);
    set.reorder(policy, permutation.read(policy));
    set.shrink_owned(policy, kept);
  }

  // Collective: drops the ghosts and sends the owned particles outside this rank's cells to
  // their owners (every sortable variable); the arrivals follow the particles that stayed.
  template <ExecutionPolicy P>
  void migrate(P policy, Body<T, D>& body) {
    ParticleSet& set = body.particles();
    if (set.ghost_count() != 0) set.set_ghost_count(0);
    const auto t0 = now(policy);
    comm::Plan plan = comm::migration_plan(policy, comm_, decomposition_, owned_positions(policy, body), work_,
                                           last_migration_ ? &*last_migration_ : nullptr);
    const auto t1 = now(policy);
    const Index owned = comm::migrate(policy, *transport_, plan, set.variables(), set.owned_count(), exchange_, work_);
    set.adopt_owned(policy, owned);
    const auto t2 = now(policy);
    timings_.plan_seconds += seconds(t0, t1);
    timings_.migration_plan_seconds += seconds(t0, t1);
    timings_.exchange_seconds += seconds(t1, t2);
    timings_.migrate_seconds += seconds(t1, t2);
    ++timings_.exchanges;
    migrated_ += plan.export_count();
    last_migration_ = std::move(plan);  // its lists serve the next migration's plan
  }

  // Collective: builds `halo` from the owned positions (anew, or in its storage where it exists)
  // and fills the ghosts with every sortable variable.
  template <ExecutionPolicy P>
  void gather(P policy, Body<T, D>& body, std::unique_ptr<Halo>& halo) {
    ParticleSet& set = body.particles();
    if (set.ghost_count() != 0) set.set_ghost_count(0);
    const auto t0 = now(policy);
    if (halo)
      halo->build(policy, comm_, decomposition_, owned_positions(policy, body), Real(width_));
    else
      halo = std::make_unique<Halo>(policy, comm_, decomposition_, owned_positions(policy, body), Real(width_), &work_);
    const auto t1 = now(policy);
    halo->gather(policy, *transport_, set, body.positions().name());
    const auto t2 = now(policy);
    timings_.plan_seconds += seconds(t0, t1);
    timings_.exchange_seconds += seconds(t1, t2);
    timings_.gather_seconds += seconds(t1, t2);
    ++timings_.exchanges;
  }
  // Collective: the named variables of the ghosts again, from their owners' current values.
  template <ExecutionPolicy P>
  void refresh(P policy, Body<T, D>& body, Halo& halo, std::span<const std::string> names) {
    const auto t0 = now(policy);
    halo.refresh(policy, *transport_, body.particles(), body.positions().name(), names);
    add_refresh_time(seconds(t0, now(policy)));
    ++timings_.exchanges;
  }

  // The refresh in two halves (Halo::refresh_begin and refresh_end), around work on the interior
  // particles that reads no ghost:
  //   refresh_begin(...);  interior pass;  refresh_end(..., [&] { border pass; });
  // On the device the ghosts' filling and `then()` (the border particles' pass) run on the side
  // stream, after the exchange and beside the main stream's interior pass, and the main stream
  // waits for them after it; so the small border pass fills the device as the interior pass
  // drains instead of running alone after it. Timed without stopping the host (marks on the
  // device's streams, read by settle_timings()): what counts is the main stream's time packing
  // and waiting for the side stream, not the time the bytes travel beside its work. On the host
  // the halves run one after the other.
  template <ExecutionPolicy P>
  void refresh_begin(P policy, Body<T, D>& body, Halo& halo, std::span<const std::string> names) {
    const Mark a = mark(policy);
    halo.refresh_begin(policy, *transport_, body.particles(), body.positions().name(), names);
    // The side stream's filling reads what the main stream wrote so far (a transport's own
    // piece, a host-staged transport's copy back).
    if constexpr (P::space == MemorySpace::device) cuda::side_stream_wait_main("halo refresh");
    spent(a, mark(policy));
  }
  template <ExecutionPolicy P, class Then>
  void refresh_end(P policy, Body<T, D>& body, Halo& halo, Then&& then) {
    if constexpr (P::space == MemorySpace::device) {
      {
        cuda::SideStreamScope side;
        halo.refresh_end(policy, body.particles());
        then();
      }
      const Mark a = mark(policy);
      cuda::main_wait_side_stream("halo refresh");
      spent(a, mark(policy));
    } else {
      const Mark a = mark(policy);
      halo.refresh_end(policy, body.particles());
      spent(a, mark(policy));
      then();
    }
    ++timings_.exchanges;
  }
  // Adds the device's marks since the last call to the timings (waits until the device passed
  // them); call it where the device is waited for anyway.
  void settle_timings() {
    if (marked_.empty()) return;
    double t = 0;
    for (const auto& [a, b] : marked_) t += cuda::seconds_between(a, b);
    marked_.clear();
    cuda::clear_time_marks();
    add_refresh_time(t);
  }

  // An on/off environment variable: true for 1, false for 0, `fallback` where unset or empty;
  // any other value stops the run with one line naming the variable.
  static bool switch_from_environment(const char* name, bool fallback) {
    const char* v = std::getenv(name);
    if (!v || !*v) return fallback;
    if (std::string(v) == "1") return true;
    if (std::string(v) == "0") return false;
    throw Error(std::string(name) + "='" + v + "': use 1 or 0");
  }

  // Whether the solver overlaps the ghosts' refreshes with the interior particles' work:
  // UNISPH_HALO_OVERLAP=1 or 0 where set, else where the transport's exchange runs beside the
  // device's work (NCCL); host-staged exchanges finish before they return, so there the split
  // passes would only add launches.
  bool overlap_refreshes() const { return switch_from_environment("UNISPH_HALO_OVERLAP", transport_->overlaps()); }

  // Whether the interior particles' passes search the owned particles' own cell lists
  // (CellLinkedList::owned_view, where the refreshes overlap): UNISPH_OWNED_VIEWS=1 or 0 where
  // set, else yes. Each keeps 4 bytes per cell of the whole domain for the fluid and the walls
  // (about 9 bytes per particle in a 10^9-particle run on four GPUs), for 6 to 8 % on four GPUs.
  static bool owned_views() { return switch_from_environment("UNISPH_OWNED_VIEWS", true); }

  // Whether the id-ordered cell lists sort only the ghosts' keys and merge them with the owned
  // particles' (CellLinkedList::sort_only_ghosts): UNISPH_GHOST_MERGE=1 or 0 where set, else yes.
  // 0 sorts every key, as before the merge: the same lists, kept to measure the two.
  static bool ghost_merge() { return switch_from_environment("UNISPH_GHOST_MERGE", true); }

  // Particles sent to another rank by migrate() since the start, on this rank.
  std::uint64_t migrated() const { return migrated_; }

 private:
  // A point in time on the policy's stream: a device event, or the host's clock (host policies
  // have finished their work when a call returns).
  struct Mark {
    int event = -1;
    std::chrono::steady_clock::time_point at{};
  };
  template <ExecutionPolicy P>
  static Mark mark(P) {
    if constexpr (P::space == MemorySpace::device) return {cuda::mark_time(), {}};
    else return {-1, std::chrono::steady_clock::now()};
  }
  void spent(const Mark& a, const Mark& b) {
    if (a.event >= 0) {
      marked_.emplace_back(a.event, b.event);
      return;
    }
    add_refresh_time(seconds(a.at, b.at));
  }
  // A refresh's time counts as exchanging too.
  void add_refresh_time(double t) {
    timings_.exchange_seconds += t;
    timings_.refresh_seconds += t;
  }

  // The owned positions in the policy's memory.
  template <ExecutionPolicy P>
  static View<const Vec<T, D>> owned_positions(P policy, Body<T, D>& body) {
    return body.positions().read(policy).subview(0, body.particles().owned_count());
  }

  // The owned positions on the host, in Real (the decomposition's histograms).
  static std::vector<PlanPosition> plan_positions(Body<T, D>& body) {
    const Index n = body.particles().owned_count();
    View<const Vec<T, D>> x = body.positions().read(MemorySpace::host);
    std::vector<PlanPosition> out(n);
    for (Index i = 0; i < n; ++i)
      for (int a = 0; a < D; ++a) out[i][a] = Real(x[i][a]);
    return out;
  }

  comm::Communicator comm_;
  std::unique_ptr<comm::Transport> transport_;
  T width_;
  T skin_;
  double rebalance_fraction_;
  comm::DecompositionMethod method_;
  double imbalance_sum_ = 0, imbalance_worst_ = 0;
  std::uint64_t checks_ = 0;
  comm::CellGrid<D> grid_{};
  comm::Decomposition<D> decomposition_;
  comm::VariableExchange exchange_;
  comm::PlanScratch work_;
  std::optional<comm::Plan> last_migration_;
  Timings timings_;
  std::vector<std::pair<int, int>> marked_;  // device marks not yet read (settle_timings)
  std::uint64_t decompositions_ = 0;
  bool measure_cut_ = true;  // the first check measures the first cut
  double reached_ = 1;       // max / mean right after the last cut
  std::uint64_t rebalances_ = 0;
  std::uint64_t migrated_ = 0;
};

}  // namespace unisph::sph
