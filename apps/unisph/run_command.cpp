// `unisph run CASE.toml`: runs a free-surface case with the weakly compressible SPH solver and
// writes a ParaView collection, observer series and a log into the output folder.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "commands.hpp"
#include "unisph/exec/policy.hpp"
#include "unisph/io/vtk_xml_writer.hpp"
#include "unisph/sph/case_file.hpp"
#include "unisph/sph/weakly_compressible_solver.hpp"

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
};

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
  explicit Progress(bool quiet) : quiet_(quiet), tty_(isatty(fileno(stderr))) {}
  template <class Solver>
  void show(Solver& solver, double end_time, double elapsed, bool last) {
    if (quiet_) return;
    if (!last && elapsed - shown_ < (tty_ ? 0.5 : 10.0)) return;
    shown_ = elapsed;
    const double fraction = std::min(1.0, solver.time() / end_time);
    const double rate = elapsed > 0 ? double(solver.acoustic_steps()) * double(solver.fluid_count()) / elapsed : 0;
    const double left = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0;
    std::fprintf(stderr, "%st = %.4g / %.4g (%5.1f%%)  steps %llu advection, %llu acoustic  %.3g particle-steps/s  %s %.0f s%s",
                 tty_ ? "\r" : "", solver.time(), end_time, 100 * fraction,
                 (unsigned long long)solver.advection_steps(), (unsigned long long)solver.acoustic_steps(), rate,
                 last ? "wall" : "left", last ? elapsed : left, tty_ && !last ? "   " : "\n");
    std::fflush(stderr);
  }

 private:
  bool quiet_;
  bool tty_;
  double shown_ = -1e9;
};

template <class T, int D>
int run_case(const sph::CaseDescription& description, PolicyKind kind, const RunOptions& options) {
  using Solver = sph::WeaklyCompressibleSolver<T, D>;
  const auto start = std::chrono::steady_clock::now();
  Solver solver(description, kind);
  const fs::path dir = options.output.empty() ? fs::path("out") / description.name : fs::path(options.output);
  fs::create_directories(dir);

  std::ofstream observers(dir / "observers.csv");
  observers.precision(10);
  observers << "# case " << description.name << " (" << description.source << "); scales: length "
            << description.length_scale << ", time " << description.time_scale << ", pressure "
            << description.pressure_scale << "\n";
  observers << "time,time_star,front,front_star,kinetic_energy,potential_energy,mass";
  for (const auto& p : description.probes) observers << ",p_" << p.name << ",p_star_" << p.name;
  observers << "\n";
  auto record = [&] {
    const sph::ObserverSample s = solver.observe();
    observers << s.time << ',' << s.time / description.time_scale << ',' << s.front << ','
              << s.front / description.length_scale << ',' << s.kinetic_energy << ',' << s.potential_energy << ','
              << s.mass;
    for (double p : s.probe_pressure) observers << ',' << p << ',' << p / description.pressure_scale;
    observers << '\n';
  };

  std::vector<io::CollectionEntry> collection;
  int snapshot = 0;
  auto write_snapshot = [&] {
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, "_%06d.vtp", snapshot++);
    auto& fluid = solver.fluid_body().particles();
    std::vector<io::PointArray> arrays;
    arrays.push_back(io::PointArray::from("ParticleId", 1, fluid.ids().to_vector()));
    arrays.push_back(vector_array<T, D>("Velocity", fluid.template variable<Vec<T, D>>("Velocity").to_vector()));
    arrays.push_back(io::PointArray::from("Density", 1, fluid.template variable<T>("Density").to_vector()));
    arrays.push_back(io::PointArray::from("Pressure", 1, fluid.template variable<T>("Pressure").to_vector()));
    const std::string fluid_file = solver.fluid_body().name() + suffix;
    io::write_vtp(dir / fluid_file, as_points<T, D>(solver.fluid_body().positions().to_vector()), arrays);
    auto& wall = solver.wall_body().particles();
    std::vector<io::PointArray> wall_arrays;
    wall_arrays.push_back(vector_array<T, D>("Normal", wall.template variable<Vec<T, D>>("Normal").to_vector()));
    const std::string wall_file = solver.wall_body().name() + suffix;
    io::write_vtp(dir / wall_file, as_points<T, D>(solver.wall_body().positions().to_vector()), wall_arrays);
    collection.push_back({solver.time(), 0, fluid_file});
    collection.push_back({solver.time(), 1, wall_file});
    io::write_pvd(dir / (description.name + ".pvd"), collection);
  };

  const double end_time = description.end_time;
  Progress progress(options.quiet);
  record();
  write_snapshot();
  double next_output = description.output_interval;
  const auto loop_start = std::chrono::steady_clock::now();
  std::string failure;
  try {
    while (solver.time() < end_time * (1 - 1e-12)) {
      const double until = std::min(next_output, end_time);
      solver.advance(until);
      record();
      if (solver.time() >= until * (1 - 1e-12)) {
        write_snapshot();
        next_output += description.output_interval;
      }
      progress.show(solver, end_time,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start).count(), false);
    }
  } catch (const sph::SimulationError& e) {
    failure = e.what();
  }
  const double loop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start).count();
  const double total_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  progress.show(solver, end_time, loop_seconds, true);
  observers.close();

  std::ostringstream log;
  log << "case: " << description.name << " (" << description.source << ")\n"
      << "dimension: " << D << "\nprecision: " << (sizeof(T) == 8 ? "double" : "float") << "\n"
      << "policy: " << to_string(kind) << (kind == PolicyKind::device ? " (" + execution_info().device_name + ")" : "")
      << "\ndx: " << description.dx << "\nsmoothing length h: " << solver.smoothing_length()
      << "\nfluid particles: " << solver.fluid_count() << "\nwall particles: " << solver.wall_count()
      << "\nsimulated time: " << solver.time() << " of " << end_time
      << "\nadvection steps: " << solver.advection_steps() << "\nacoustic steps: " << solver.acoustic_steps()
      << "\nsnapshots: " << snapshot << "\nwall time (time loop, output included): " << loop_seconds << " s"
      << "\nwall time (total): " << total_seconds << " s"
      << "\nfluid-particle acoustic steps per second: "
      << (loop_seconds > 0 ? double(solver.acoustic_steps()) * double(solver.fluid_count()) / loop_seconds : 0) << "\n";
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
  command->add_option("case", options.case_file, "the case file, e.g. cases/dambreak_2d.toml")->required();
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
  command->callback([] {
    sph::CaseDescription description = sph::read_case_file(options.case_file);
    if (options.dx > 0) {
      description.dx = options.dx;
      for (int a = 0; a < description.dimension; ++a)
        if (description.column[a] < description.dx)
          throw sph::CaseFileError("--dx " + std::to_string(options.dx) + ": larger than the column of " +
                                   options.case_file);
    }
    if (options.end_time > 0) {
      description.end_time = options.end_time;
      description.output_interval = std::min(description.output_interval, options.end_time);
    }
    set_host_threads(options.threads);
    PolicyKind kind = PolicyKind::par;
    if (!options.policy.empty())
      kind = parse_policy(options.policy);
    else if (policy_available(PolicyKind::device))
      kind = PolicyKind::device;
    require_policy(kind);
    const bool single = options.precision == "float";
    int status = 0;
    if (description.dimension == 2)
      status = single ? run_case<float, 2>(description, kind, options) : run_case<double, 2>(description, kind, options);
    else
      status = single ? run_case<float, 3>(description, kind, options) : run_case<double, 3>(description, kind, options);
    if (status != 0) throw CLI::RuntimeError(status);
  });
}

}  // namespace unisph::app
