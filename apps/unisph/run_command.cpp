// `unisph run CASE.toml`: runs a free-surface case with the weakly compressible SPH solver and
// writes a ParaView collection, observer series and a log into the output folder.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <thread>
#include <string>
#include <unistd.h>
#include <vector>

#include "commands.hpp"
#include "unisph/comm/communicator.hpp"
#include "unisph/exec/policy.hpp"
#include "unisph/io/vtk_xml_writer.hpp"
#include "unisph/solver/case_file.hpp"
#include "unisph/solver/solver_checkpoint.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"

namespace unisph::app {
namespace {

namespace fs = std::filesystem;

struct RunOptions {
  std::string case_file;
  std::string policy;  // empty: the device where present, else par
  std::string precision = "double";
  double dx = 0;
  double end_time = 0;
  std::string output;
  int threads = 0;
  bool quiet = false;
  bool no_snapshots = false;
  double checkpoint_every = -1;  // < 0: the case file's time.checkpoint_every
  std::string restart;           // a checkpoint to continue from
};

// What `unisph run` itself needs to continue a run's output after a restart; stored in the
// checkpoint's observer block as text ("key value" lines, numbers with 17 digits).
struct RunState {
  double next_output = 0;
  double next_checkpoint = 0;
  int snapshot = 0;
  std::uint64_t observer_rows = 0;
  std::vector<io::CollectionEntry> collection;

  std::string encode() const {
    std::ostringstream s;
    s.precision(17);
    s << "next_output " << next_output << "\nnext_checkpoint " << next_checkpoint << "\nsnapshot " << snapshot
      << "\nobserver_rows " << observer_rows << "\n";
    for (const io::CollectionEntry& e : collection) s << "entry " << e.time << ' ' << e.part << ' ' << e.file << "\n";
    return s.str();
  }
  static RunState decode(const std::string& text, const std::string& source) {
    RunState r;
    std::istringstream in(text);
    std::string key;
    while (in >> key) {
      if (key == "next_output") in >> r.next_output;
      else if (key == "next_checkpoint") in >> r.next_checkpoint;
      else if (key == "snapshot") in >> r.snapshot;
      else if (key == "observer_rows") in >> r.observer_rows;
      else if (key == "entry") {
        io::CollectionEntry e{};
        in >> e.time >> e.part >> e.file;
        r.collection.push_back(e);
      } else {
        throw io::CheckpointError("checkpoint " + source + ": unknown run-state entry '" + key + "'");
      }
      if (!in) throw io::CheckpointError("checkpoint " + source + ": run-state entry '" + key + "' has no valid value");
    }
    return r;
  }
};

// On a restart into a folder that holds the run's observers.csv: keep its header and the rows
// written up to the checkpoint (a crashed run may have written more), then append.
void keep_observer_rows(const fs::path& file, std::uint64_t rows) {
  std::ifstream in(file);
  std::string line, kept;
  std::uint64_t data = 0;
  while (std::getline(in, line)) {
    const bool header = line.rfind("#", 0) == 0 || line.rfind("time,", 0) == 0;
    if (!header && data++ >= rows) break;
    kept += line + "\n";
  }
  io::write_file_atomically(file, kept);
}

template <class S, int D, class Source>
std::vector<S> as_points(const std::vector<Source>& x) {
  std::vector<S> out(x.size() * 3, S(0));
  for (std::size_t i = 0; i < x.size(); ++i)
    for (int a = 0; a < D; ++a) out[3 * i + a] = S(x[i][a]);
  return out;
}

template <class S, int D, class Source>
io::PointArray vector_array(const std::string& name, const std::vector<Source>& v) {
  return io::PointArray::from(name, 3, as_points<S, D>(v));
}

class Progress {
 public:
  // A restarted run starts at (start_time, start_steps); rates count from there.
  // particles: the fluid particles of all ranks at the start (the rate's factor).
  Progress(bool quiet, double start_time, std::uint64_t start_steps, double particles)
      : quiet_(quiet), tty_(isatty(fileno(stderr))), start_time_(start_time), start_steps_(start_steps),
        particles_(particles) {}
  template <class Solver>
  void show(Solver& solver, double end_time, double elapsed, bool last) {
    if (quiet_) return;
    if (!last && elapsed - shown_ < (tty_ ? 0.5 : 10.0)) return;
    shown_ = elapsed;
    const double fraction = std::min(1.0, solver.time() / end_time);
    const double rate = elapsed > 0 ? double(solver.acoustic_steps() - start_steps_) * particles_ / elapsed : 0;
    const double done = (solver.time() - start_time_) / end_time;
    const double left = done > 0 ? elapsed * (1 - fraction) / done : 0;
    std::fprintf(stderr, "%st = %.4g / %.4g (%5.1f%%)  steps %llu advection, %llu acoustic  %.3g particle-steps/s  %s %.0f s%s",
                 tty_ ? "\r" : "", solver.time(), end_time, 100 * fraction,
                 (unsigned long long)solver.advection_steps(), (unsigned long long)solver.acoustic_steps(), rate,
                 last ? "wall" : "left", last ? elapsed : left, tty_ && !last ? "   " : "\n");
    std::fflush(stderr);
  }

 private:
  bool quiet_;
  bool tty_;
  double start_time_;
  std::uint64_t start_steps_;
  double particles_;
  double shown_ = -1e9;
};

// On several ranks (mpirun): every rank runs the solver on its part of the domain and writes
// its piece of each snapshot; rank 0 alone writes the observers, loads, collection and log.
template <class T, int D>
int run_case(const sph::CaseDescription& description, PolicyKind kind, const RunOptions& options,
             const comm::Communicator& world) {
  using Solver = sph::WeaklyCompressibleSolver<T, D>;
  const auto start = std::chrono::steady_clock::now();
  const bool restarted = !options.restart.empty();
  const bool lead = world.rank() == 0;
  const bool ranks = world.size() > 1;
  // A restarted run takes its settled state from the checkpoint.
  if (lead && !restarted && description.settling_time > 0 && !options.quiet)
    std::fprintf(stderr, "settling: %g time units with the velocity damped at %g per unit of time...\n", description.settling_time,
                description.settling_damping);
  // A GPU's memory for this run: the free memory before the solver less the least seen at the
  // outputs (particles, ghosts, lists and the kept scratch; the CUDA context left out).
  const bool on_device = kind == PolicyKind::device;
  const std::uint64_t free_before = on_device ? device_free_bytes() : 0;
  std::uint64_t least_free = free_before;
  const auto sample_device_memory = [&] {
    if (on_device) least_free = std::min(least_free, device_free_bytes());
  };
  Solver solver(description, kind, world, !restarted);
  RunState run;
  run.next_output = description.output_interval;
  run.next_checkpoint = description.checkpoint_every;
  if (restarted) {
    run = RunState::decode(solver.restore_checkpoint(options.restart), options.restart);
    // The checkpoint interval may have been changed for the restarted run.
    if (description.checkpoint_every > 0 && !(run.next_checkpoint > solver.time()))
      run.next_checkpoint = solver.time() + description.checkpoint_every;
  }
  const fs::path dir = options.output.empty() ? fs::path("out") / description.name : fs::path(options.output);
  fs::create_directories(dir);
  const fs::path checkpoint_file = dir / "checkpoint.bin";

  // Only the lead rank touches observers.csv: another rank's check or rewrite would race with it.
  const bool continue_observers = lead && restarted && fs::exists(dir / "observers.csv");
  if (continue_observers) keep_observer_rows(dir / "observers.csv", run.observer_rows);
  std::ofstream observers;
  if (lead) observers.open(dir / "observers.csv", continue_observers ? std::ios::app : std::ios::trunc);
  observers.precision(10);
  if (lead && !continue_observers) {
    observers << "# case " << description.name << " (" << description.source << "); scales: length "
              << description.length_scale << ", time " << description.time_scale << ", pressure "
              << description.pressure_scale << (restarted ? "; restarted from " + options.restart : std::string())
              << "\n";
    observers << "time,time_star,front,front_star,kinetic_energy,potential_energy,mass";
    for (const auto& p : description.probes) observers << ",p_" << p.name << ",p_star_" << p.name;
    for (const auto& v : description.velocity_probes)
      for (int a = 0; a < description.dimension; ++a) observers << ",velocity_" << v.name << "_" << "xyz"[a];
    for (const auto& g : description.gauges) observers << ",gauge_" << g.name;
    observers << "\n";
  }
  // report.loads: one row per advection step (the mean over its acoustic steps), the same steps as
  // the observers' rows after their first (t = 0). Columns <body>_fx, _fy(, _fz), then the moment
  // about report.moment_point: <body>_mz in 2D, <body>_mx, _my, _mz in 3D.
  const bool with_loads = description.loads;
  const bool write_loads = with_loads && lead;
  const bool continue_loads = write_loads && restarted && fs::exists(dir / "loads.csv");
  if (continue_loads) keep_observer_rows(dir / "loads.csv", run.observer_rows > 0 ? run.observer_rows - 1 : 0);
  std::ofstream loads;
  std::vector<double> largest_force(solver.wall_bodies().size(), 0.0);
  if (write_loads) {
    loads.open(dir / "loads.csv", continue_loads ? std::ios::app : std::ios::trunc);
    loads.precision(10);
    if (!continue_loads) {
      loads << "# case " << description.name << ": each wall body's force and moment about (";
      for (int a = 0; a < D; ++a) loads << (a ? ", " : "") << description.moment_point[std::size_t(a)];
      loads << "), the mean over each advection step's acoustic steps\ntime";
      for (const sph::WallBodyCount& b : solver.wall_bodies()) {
        for (int a = 0; a < D; ++a) loads << ',' << b.name << "_f" << "xyz"[a];
        if (D == 2) loads << ',' << b.name << "_mz";
        else for (int a = 0; a < 3; ++a) loads << ',' << b.name << "_m" << "xyz"[a];
      }
      loads << "\n";
    }
  }
  auto record_loads = [&] {
    if (!write_loads) return;
    const std::vector<sph::WallLoadSample>& l = solver.loads();
    loads << solver.time();
    for (std::size_t b = 0; b < l.size(); ++b) {
      double squared = 0;
      for (double f : l[b].force) loads << ',' << f, squared += f * f;
      for (double m : l[b].moment) loads << ',' << m;
      largest_force[b] = std::max(largest_force[b], std::sqrt(squared));
    }
    loads << '\n';
  };

  auto record = [&] {
    ++run.observer_rows;
    sample_device_memory();
    const sph::ObserverSample s = solver.observe();  // collective on several ranks
    if (!lead) return;
    observers << s.time << ',' << s.time / description.time_scale << ',' << s.front << ','
              << s.front / description.length_scale << ',' << s.kinetic_energy << ',' << s.potential_energy << ','
              << s.mass;
    for (double p : s.probe_pressure) observers << ',' << p << ',' << p / description.pressure_scale;
    for (double v : s.probe_velocity) observers << ',' << v;
    for (double g : s.gauge_elevation) observers << ',' << g;
    observers << '\n';
  };

  // Several ranks: each writes <body>_<snapshot>_r<rank>.vtp, and rank 0 the .pvtp joining them.
  const auto piece_name = [&](const std::string& body, const char* number, int rank) {
    return body + number + (ranks ? "_r" + std::to_string(rank) + ".vtp" : std::string(".vtp"));
  };
  const auto series_file = [&](const std::string& body, const char* number, const std::vector<io::PointArray>& arrays) {
    if (!ranks) return piece_name(body, number, 0);
    std::vector<std::string> pieces;
    for (int r = 0; r < world.size(); ++r) pieces.push_back(piece_name(body, number, r));
    const std::string file = body + number + ".pvtp";
    if (lead) io::write_pvtp(dir / file, io::PointArray::vtk_type_of<T>(), arrays, pieces);
    return file;
  };
  auto write_snapshot = [&] {
    if (options.no_snapshots) return;
    char number[32];
    std::snprintf(number, sizeof number, "_%06d", run.snapshot++);
    auto& fluid = solver.fluid_body().particles();
    std::vector<io::PointArray> arrays;
    // Owned particles only: a periodic case's images (ghosts after them) are copies.
    const auto owned = [](auto values, Index count) {
      values.resize(count);
      return values;
    };
    const Index fluid_count = fluid.owned_count();
    arrays.push_back(io::PointArray::from("ParticleId", 1, owned(fluid.ids().to_vector(), fluid_count)));
    arrays.push_back(vector_array<T, D>("Velocity", owned(fluid.template variable<Vec<T, D>>("Velocity").to_vector(), fluid_count)));
    arrays.push_back(io::PointArray::from("Density", 1, owned(fluid.template variable<T>("Density").to_vector(), fluid_count)));
    arrays.push_back(io::PointArray::from("Pressure", 1, owned(fluid.template variable<T>("Pressure").to_vector(), fluid_count)));
    io::write_vtp(dir / piece_name(solver.fluid_body().name(), number, world.rank()),
                  as_points<T, D>(owned(solver.fluid_body().positions().to_vector(), fluid_count)), arrays);
    run.collection.push_back({solver.time(), 0, series_file(solver.fluid_body().name(), number, arrays)});
    // Each wall body to a series of its own (its name, then the snapshot's number): a wall
    // particle's body follows from its id (the first body's ids come first, then the second's...).
    auto& wall = solver.wall_body().particles();
    const std::vector<sph::WallBodyCount>& bodies = solver.wall_bodies();
    const Index wall_count = wall.owned_count();
    const std::vector<std::uint64_t> ids = owned(wall.ids().to_vector(), wall_count);
    const std::vector<Vec<T, D>> positions = owned(solver.wall_body().positions().to_vector(), wall_count);
    const std::vector<Vec<T, D>> normals = owned(wall.template variable<Vec<T, D>>("Normal").to_vector(), wall_count);
    const std::vector<Vec<T, D>> wall_velocity =
        wall.variables().contains("Velocity") ? owned(wall.template variable<Vec<T, D>>("Velocity").to_vector(), wall_count)
                                              : std::vector<Vec<T, D>>{};
    std::vector<std::uint64_t> first(bodies.size() + 1, wall.first_id());
    for (std::size_t k = 0; k < bodies.size(); ++k) first[k + 1] = first[k] + bodies[k].count;
    for (std::size_t k = 0; k < bodies.size(); ++k) {
      std::vector<Vec<T, D>> x, n;
      std::vector<std::uint64_t> id;
      for (std::size_t i = 0; i < ids.size(); ++i)
        if (ids[i] >= first[k] && ids[i] < first[k + 1]) x.push_back(positions[i]), n.push_back(normals[i]), id.push_back(ids[i]);
      std::vector<io::PointArray> wall_arrays;
      wall_arrays.push_back(io::PointArray::from("ParticleId", 1, id));
      wall_arrays.push_back(vector_array<T, D>("Normal", n));
      if (!wall_velocity.empty()) {  // moving walls
        std::vector<Vec<T, D>> v;
        for (std::size_t i = 0; i < ids.size(); ++i)
          if (ids[i] >= first[k] && ids[i] < first[k + 1]) v.push_back(wall_velocity[i]);
        wall_arrays.push_back(vector_array<T, D>("Velocity", v));
      }
      io::write_vtp(dir / piece_name(bodies[k].name, number, world.rank()), as_points<T, D>(x), wall_arrays);
      run.collection.push_back({solver.time(), int(k + 1), series_file(bodies[k].name, number, wall_arrays)});
    }
    if (lead) io::write_pvd(dir / (description.name + ".pvd"), run.collection);
  };
  // Taken after the advection step that reaches the checkpoint time (not by shortening a
  // step), so a run with checkpoints takes the same steps as one without.
  int checkpoints = 0;
  auto checkpoint_if_due = [&] {
    if (description.checkpoint_every <= 0 || solver.time() < run.next_checkpoint * (1 - 1e-12)) return;
    while (run.next_checkpoint <= solver.time() * (1 + 1e-12)) run.next_checkpoint += description.checkpoint_every;
    solver.write_checkpoint(checkpoint_file, run.encode());
    ++checkpoints;
  };

  const double end_time = description.end_time;
  const auto case_made = std::chrono::steady_clock::now();
  if (!restarted) {
    record();
    write_snapshot();
  }
  const std::uint64_t first_acoustic_step = solver.acoustic_steps();
  const std::uint64_t fluid_particles = solver.fluid_count_all_ranks();
  Progress progress(options.quiet || !lead, solver.time(), first_acoustic_step, double(fluid_particles));
  const auto timings_before_loop = solver.rank_timings();  // set-up and NCCL's start left out
  const auto loop_start = std::chrono::steady_clock::now();
  const double setup_seconds = std::chrono::duration<double>(loop_start - start).count();
  const double first_output_seconds = std::chrono::duration<double>(loop_start - case_made).count();
  double snapshot_seconds = 0;  // writing snapshots within the time loop
  std::string failure;
  try {
    while (solver.time() < end_time * (1 - 1e-12)) {
      const double until = std::min(run.next_output, end_time);
      solver.advance(until);
      record();
      record_loads();
      if (solver.time() >= until * (1 - 1e-12)) {
        const auto written = std::chrono::steady_clock::now();
        write_snapshot();
        snapshot_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - written).count();
        run.next_output += description.output_interval;
      }
      checkpoint_if_due();
      progress.show(solver, end_time,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start).count(), false);
    }
  } catch (const sph::SimulationError& e) {
    failure = e.what();
  } catch (const comm::RankFailure& e) {  // several ranks: every rank has it, with one line
    failure = e.what();
  }
  const double loop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start).count();
  const double total_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  progress.show(solver, end_time, loop_seconds, true);
  observers.close();
  // Several ranks: each rank's GPU and particles, for the log (collective).
  sample_device_memory();
  const std::vector<double> rank_device_bytes = world.allgather(double(free_before - least_free));
  const DeviceMemoryUse memory_use = on_device ? device_memory_use() : DeviceMemoryUse{};
  const std::vector<double> rank_making = world.allgather(solver.setup_seconds().first);
  const std::vector<double> rank_placing = world.allgather(solver.setup_seconds().second);
  const std::vector<double> rank_allocated_peak = world.allgather(double(memory_use.peak_bytes));
  const std::vector<std::uint64_t> rank_fluid = world.allgather(std::uint64_t(solver.fluid_count()));
  const std::vector<std::uint64_t> rank_wall = world.allgather(std::uint64_t(solver.wall_count()));
  const std::vector<std::uint64_t> rank_migrated = world.allgather(solver.particles_migrated());
  const std::vector<std::uint64_t> rank_local = world.allgather(std::uint64_t(world.local_rank()));
  // Each rank's time in the time loop: its acoustic steps (ghost refreshes among them) and the
  // ends of its advection steps (migration, halo with its plan, sort and lists).
  const auto after = solver.rank_timings();
  const auto& before = timings_before_loop;
  const std::vector<double> rank_acoustic = world.allgather(after.acoustic_loop_seconds - before.acoustic_loop_seconds);
  const std::vector<double> rank_refresh = world.allgather(after.refresh_seconds - before.refresh_seconds);
  const std::vector<double> rank_loop_refresh =
      world.allgather(after.acoustic_refresh_seconds - before.acoustic_refresh_seconds);
  const std::vector<double> rank_step_end = world.allgather(after.step_end_seconds - before.step_end_seconds);
  const std::vector<double> rank_speed_wait = world.allgather(after.speed_wait_seconds - before.speed_wait_seconds);
  const std::vector<double> rank_sort = world.allgather(after.sort_seconds - before.sort_seconds);
  const std::vector<double> rank_rebuild = world.allgather(after.rebuild_seconds - before.rebuild_seconds);
  const std::vector<double> rank_migration_plan =
      world.allgather(after.migration_plan_seconds - before.migration_plan_seconds);
  const std::vector<double> rank_migrate = world.allgather(after.migrate_seconds - before.migrate_seconds);
  const std::vector<double> rank_gather = world.allgather(after.gather_seconds - before.gather_seconds);
  const std::vector<double> rank_plan = world.allgather(after.plan_seconds - before.plan_seconds);
  const std::vector<double> rank_exchange = world.allgather(after.exchange_seconds - before.exchange_seconds);
  const auto balance = solver.rank_balance();
  const std::vector<double> rank_ghosts = world.allgather(balance.mean_fluid_ghosts);
  std::uint64_t wall_particles = 0;
  for (std::uint64_t n : rank_wall) wall_particles += n;
  const std::uint64_t fluid_now = solver.fluid_count_all_ranks();
  if (!lead) return failure.empty() ? 0 : 2;

  std::ostringstream log;
  log << "case: " << description.name << " (" << description.source << ")\n"
      << "dimension: " << D << "\nprecision: " << (sizeof(T) == 8 ? "double" : "float") << "\n"
      << "policy: " << to_string(kind) << (kind == PolicyKind::device ? " (" + execution_info().device_name + ")" : "")
      << "\ndx: " << description.dx << "\nsmoothing length h: " << solver.smoothing_length()
      << "\nfluid particles: " << fluid_now << "\nwall particles: " << wall_particles;
  if (on_device) {
    double device_bytes = 0;
    for (double b : rank_device_bytes) device_bytes += b;
    log << "\ndevice memory (the free memory before the run less the least seen at its outputs"
        << (ranks ? ", all GPUs" : "") << "): " << device_bytes / double(1ull << 30) << " GiB, "
        << device_bytes / double(std::max<std::uint64_t>(1, fluid_now + wall_particles))
        << " bytes per fluid and wall particle (ghosts, neighbour lists and scratch included)";
    // Where it went: unisph's own blocks by use (rank 0's), the rest is the libraries' (NCCL, CUDA).
    const auto gib = [](double b) { return b / double(1ull << 30); };
    log << "\ndevice memory unisph allocated" << (ranks ? " (rank 0)" : "") << ": at most " << gib(double(memory_use.peak_bytes))
        << " GiB at once, " << gib(double(memory_use.bytes)) << " GiB at the end, of which";
    // Every use, largest first: the ledger is what a memory budget is checked against.
    const std::size_t shown = memory_use.groups.size();
    for (std::size_t k = 0; k < shown; ++k)
      log << (k ? "," : "") << " " << memory_use.groups[k].what << " " << gib(double(memory_use.groups[k].bytes)) << " GiB"
          << (memory_use.groups[k].blocks > 1 ? " (" + std::to_string(memory_use.groups[k].blocks) + " blocks)" : std::string());
  }
  if (ranks) {
    log << "\nranks: " << world.size() << " (domain cut "
        << (balance.method == "bisection" ? "by recursive bisection" : "along the Morton curve") << "; cut again "
        << solver.rebalances() << " times; transport " << solver.transport() << "; "
        << (solver.made_in_shares() ? "each rank made only its own particles" : "every rank made the whole case and kept its share")
        << ")"
        << "\nfluid balance (max / mean of the ranks' fluid particles at each advection step): mean "
        << balance.mean_imbalance << ", worst " << balance.worst_imbalance;
    for (int r = 0; r < world.size(); ++r)
      log << "\nrank " << r << ": " << (kind == PolicyKind::device ? "GPU " + std::to_string(rank_local[std::size_t(r)]) + " of its node"
                                                                  : "local rank " + std::to_string(rank_local[std::size_t(r)]))
          << ", " << rank_fluid[std::size_t(r)] << " fluid and " << rank_wall[std::size_t(r)]
          << " wall particles owned at the end, " << rank_migrated[std::size_t(r)] << " particles sent to other ranks, "
          << rank_ghosts[std::size_t(r)] << " fluid ghosts on average"
          << (on_device ? ", device memory " + std::to_string(rank_device_bytes[std::size_t(r)] / double(1ull << 30)) +
                              " GiB (unisph's own at most " +
                              std::to_string(rank_allocated_peak[std::size_t(r)] / double(1ull << 30)) + " GiB)"
                        : std::string())
          << "; "
          << "time loop: acoustic steps " << rank_acoustic[std::size_t(r)] << " s (ghost refreshes in them "
          << rank_loop_refresh[std::size_t(r)] << " s; waiting for the other ranks in the largest speed's reductions "
          << rank_speed_wait[std::size_t(r)] << " s), advection-step ends " << rank_step_end[std::size_t(r)]
          << " s (migration " << rank_migrate[std::size_t(r)] << " s, halo " << rank_gather[std::size_t(r)]
          << " s, plans " << rank_plan[std::size_t(r)] << " s of which the migrations' "
          << rank_migration_plan[std::size_t(r)] << " s, sort " << rank_sort[std::size_t(r)]
          << " s, cell lists and records " << rank_rebuild[std::size_t(r)] << " s); all ghost refreshes " << rank_refresh[std::size_t(r)]
          << " s; exchanging and plans "
          << 1e3 * (rank_plan[std::size_t(r)] + rank_exchange[std::size_t(r)]) /
                 double(std::max<std::uint64_t>(1, solver.acoustic_steps() - first_acoustic_step))
          << " ms per acoustic step";
  } else {
    log << "\ntime loop: acoustic steps " << rank_acoustic[0] << " s, advection-step ends " << rank_step_end[0]
        << " s (sort " << rank_sort[0] << " s, cell lists and records " << rank_rebuild[0] << " s)";
  }
  for (const sph::WallBodyCount& b : solver.wall_bodies()) log << "\nwall body " << b.name << ": " << b.count << " particles";
  for (std::size_t k = 0; k < description.obstacles.size(); ++k)
    log << "\nobstacle " << k + 1 << ": " << solver.obstacle_wall_counts()[k] << " wall particles from "
        << description.obstacles[k].file;
  if (!description.obstacles.empty() || description.general())
    log << "\nfluid lattice points removed next to walls: " << solver.removed_fluid_count();
  for (const sph::RelaxedBodyReport& r : solver.relaxed_bodies())
    log << "\nrelaxed body " << r.name << ": " << r.particles << " particles, " << r.iterations
        << " iterations, error |sum grad W V + G| h mean " << r.mean_error << ", max " << r.max_error;
  if (description.domain.leaving == "remove")
    log << "\nfluid particles that left the domain (removed): " << solver.left_domain_count() << ", mass "
        << solver.left_domain_mass();
  if (const sph::SettlingReport& settled = solver.settling(); settled.advection_steps > 0)
    log << "\nsettling before t = 0: " << settled.time << " time units, " << settled.advection_steps
        << " advection and " << settled.acoustic_steps << " acoustic steps, " << settled.seconds << " s";
  if (with_loads) {
    loads.close();
    const std::vector<sph::WallLoadSample>& l = solver.loads();
    for (std::size_t b = 0; b < l.size() && b < solver.wall_bodies().size(); ++b) {
      log << "\nloads on " << solver.wall_bodies()[b].name << " (loads.csv): force at the end (";
      for (std::size_t a = 0; a < l[b].force.size(); ++a) log << (a ? ", " : "") << l[b].force[a];
      log << "), moment (";
      for (std::size_t a = 0; a < l[b].moment.size(); ++a) log << (a ? ", " : "") << l[b].moment[a];
      log << "), largest |force| " << largest_force[b];
    }
  }
  log
      << "\nsimulated time: " << solver.time() << " of " << end_time
      << "\nadvection steps: " << solver.advection_steps() << "\nacoustic steps: " << solver.acoustic_steps()
      << "\nsnapshots: " << run.snapshot << "\ncheckpoints written: " << checkpoints
      << (checkpoints ? " (" + checkpoint_file.string() + ")" : std::string())
      << (restarted ? "\nrestarted from: " + options.restart + " (acoustic steps before it: " +
                          std::to_string(first_acoustic_step) + ")"
                    : std::string())
      << "\nwall time setting up (making the case, settling, cutting it among ranks, the first output): "
      << setup_seconds << " s (making the particles " << *std::max_element(rank_making.begin(), rank_making.end())
      << " s, placing them " << *std::max_element(rank_placing.begin(), rank_placing.end()) << " s"
      << (ranks ? ", the slowest rank's" : "") << "; the first output " << first_output_seconds << " s)"
      << "\nwall time (time loop, output included): " << loop_seconds << " s"
      << "\nwall time (total): " << total_seconds << " s"
      << "\nwall time writing snapshots in the time loop: " << snapshot_seconds << " s"
      << "\nfluid-particle acoustic steps per second: "
      << (loop_seconds > 0
              ? double(solver.acoustic_steps() - first_acoustic_step) * double(fluid_particles) / loop_seconds
              : 0)
      << "\nfluid-particle acoustic steps per second, snapshots excluded: "
      << (loop_seconds > snapshot_seconds
              ? double(solver.acoustic_steps() - first_acoustic_step) * double(fluid_particles) /
                    (loop_seconds - snapshot_seconds)
              : 0)
      << "\n";
  if (!failure.empty()) log << "FAILED: " << failure << "\n";
  std::ofstream(dir / "run.log") << log.str();
  if (!options.quiet) std::fputs(log.str().c_str(), stdout);
  if (!failure.empty()) {
    std::fprintf(stderr, "unisph run: the simulation failed: %s (the last good snapshot is kept in %s)\n",
                 failure.c_str(), dir.string().c_str());
    return 2;
  }
  return 0;
}

}  // namespace

void add_run_command(CLI::App& app) {
  CLI::App* command = app.add_subcommand("run", "run a case file (TOML) with the weakly compressible SPH solver");
  static RunOptions options;
  command->add_option("case", options.case_file,
                      "the case file, e.g. cases/dambreak_2d.toml (with --restart: optional, the checkpoint holds the case)");
  command->add_option("--policy", options.policy,
                      "where kernels run: seq, par or device (default: the device where one is present, else par)")
      ->check(CLI::IsMember({"seq", "par", "device"}));
  command->add_option("--precision", options.precision, "floating type of the computation")
      ->check(CLI::IsMember({"float", "double"}))
      ->capture_default_str();
  command->add_option("--dx", options.dx, "particle spacing (overrides geometry.dx)")->check(CLI::PositiveNumber);
  command->add_option("--end-time", options.end_time, "simulated end time (overrides time.end)")
      ->check(CLI::PositiveNumber);
  command->add_option("--output", options.output, "output folder (default: out/<case name>)");
  command->add_option("--threads", options.threads, "CPU threads for the par policy (0: all)")
      ->check(CLI::NonNegativeNumber);
  command->add_flag("--quiet", options.quiet, "no progress display and no summary on the terminal");
  command->add_flag("--no-snapshots", options.no_snapshots,
                    "write no particle snapshots (the observers, loads, checkpoints and log only): for runs too large to "
                    "write, and benchmarks");
  command->add_option("--checkpoint-every", options.checkpoint_every,
                      "simulated time between checkpoints, written to OUTPUT/checkpoint.bin (overrides "
                      "time.checkpoint_every; 0: none)")
      ->check(CLI::NonNegativeNumber);
  command->add_option("--restart", options.restart,
                      "continue from a checkpoint file (same case physics, precision and dimension; any policy)");
  command->callback([command] {
    if (options.case_file.empty() && options.restart.empty())
      throw CLI::RequiredError("a case file (or --restart CHECKPOINT)");
    std::string precision = options.precision;
    sph::CaseDescription description;
    if (!options.restart.empty()) {
      const sph::CheckpointSummary summary = sph::read_checkpoint_summary(options.restart);
      if (command->count("--precision") && precision != summary.precision)
        throw io::CheckpointError("checkpoint " + options.restart + ": holds a " + summary.precision +
                                  " run; --precision " + precision + " cannot continue it");
      if (options.dx > 0 && options.dx != summary.description.dx)
        throw io::CheckpointError("checkpoint " + options.restart + ": holds a run at dx = " +
                                  std::to_string(summary.description.dx) + "; --dx cannot change it");
      if (!options.case_file.empty()) {
        const sph::CaseDescription file = sph::read_case_file(options.case_file);
        if (const std::string d = sph::physics_difference(file, summary.description); !d.empty() &&
            d.rfind("geometry.dx", 0) != 0)
          throw io::CheckpointError("checkpoint " + options.restart + ": was written for another case than " +
                                    options.case_file + ": " + d);
      }
      precision = summary.precision;
      description = summary.description;
      options.dx = 0;
    } else {
      description = sph::read_case_file(options.case_file);
    }
    if (options.checkpoint_every >= 0) description.checkpoint_every = options.checkpoint_every;
    if (options.dx > 0) {
      description.dx = options.dx;
      for (int a = 0; a < int(description.column.size()); ++a)  // the short form (the general form's bodies check themselves)
        if (description.column[std::size_t(a)] < description.dx)
          throw sph::CaseFileError("--dx " + std::to_string(options.dx) + ": larger than the column of " +
                                   options.case_file);
    }
    if (options.end_time > 0) {
      description.end_time = options.end_time;
      description.output_interval = std::min(description.output_interval, options.end_time);
    }
    const comm::Communicator world = comm::Communicator::world();
    if (world.size() > 1) {
      // One GPU per rank (its number on its node), before anything touches the GPU; the CPU
      // threads shared among the node's ranks unless --threads says otherwise.
      select_device(world.local_rank());
      if (options.threads == 0) options.threads = std::max(1, int(std::thread::hardware_concurrency()) / world.local_size());
    }
    set_host_threads(options.threads);
    PolicyKind kind = PolicyKind::par;
    if (!options.policy.empty())
      kind = parse_policy(options.policy);
    else if (policy_available(PolicyKind::device))
      kind = PolicyKind::device;
    require_policy(kind);
    const bool single = precision == "float";
    int status = 0;
    if (description.dimension == 2)
      status = single ? run_case<float, 2>(description, kind, options, world)
                      : run_case<double, 2>(description, kind, options, world);
    else
      status = single ? run_case<float, 3>(description, kind, options, world)
                      : run_case<double, 3>(description, kind, options, world);
    if (status != 0) throw CLI::RuntimeError(status);
  });
}

}  // namespace unisph::app
