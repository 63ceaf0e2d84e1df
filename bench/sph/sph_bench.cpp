// The dam break timed on each policy, float and double (issue 4, "Benchmarks"):
//   2D (cases/dambreak_2d.toml) at dx = H/40, H/80, H/160, H/320
//   3D (cases/dambreak_3d.toml) at dx = 0.05, 0.025, 0.0125, 0.00625 (H = 1)
// and, in 3D, the same case in the general form (SphDamBreakGeneral: cases/dambreak_general_3d.toml,
// the tank as shapes) and with an STL pillar in the water's path (SphDamBreakStl:
// cases/dambreak_stl_3d.toml), so that the forms' speeds can be compared (issue 21); and the
// cost of a moving wall (issue 22): SphMovingWall times cases/piston_flume_2d.toml at dx = d/50
// and d/100 with its paddle moving and, the same particles, with the paddle held at rest (its
// translation removed), from t = 0 (the water stays near its lattice in a flume, so no
// checkpoint is needed) over the same 1,000 acoustic steps.
// Each is restarted from a checkpoint at t sqrt(g/H) = 6 (after the impact, not the first
// steps of a lattice) and timed over 1,000 acoustic steps (whole advection steps: the count
// reported is the one run). The bench makes a missing checkpoint itself (in a child process,
// on the fastest policy present) and keeps it in the cache folder for the next runs.
//
// Options (before Google Benchmark's own):
//   --sph_cache=DIR        checkpoint cache (else $UNISPH_SPH_BENCH_CACHE, else
//                          $XDG_CACHE_HOME/unisph/sph_bench, else ~/.cache/unisph/sph_bench)
//   --sph_cases=DIR        the case files (else $UNISPH_CASES_DIR, else ./cases, else the
//                          source tree's cases/)
//   --sph_steps=N          acoustic steps timed (default 1000)
//   --sph_checkpoint_time=T  t sqrt(g/H) of the checkpoint (default 6)
// Select cases with --benchmark_filter, e.g. 'SphDamBreak/2D/H_40/double/par' or '/3D/.*/gpu'.
//
// Counters: fluid and wall particles, acoustic and advection steps timed,
// fluid_steps_per_s (fluid-particle acoustic steps per second), pressure_relaxation_ms (one
// pass of the momentum kernel alone, the mean of repeated passes) and the same per million
// fluid particles, candidate and neighbour pairs of that pass (fluid-fluid + fluid-wall) and
// per second of it, device_bytes_per_particle (peak difference of cudaMemGetInfo over the
// restored run, the pass and the pair counts, CUB temporary storage and cell lists included,
// divided by fluid + wall particles; 0 on the CPU). The device's scratch storage is grown and
// kept by the process, so run one case per process, or cases in the registered (ascending)
// order, for that figure to include it.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "unisph/exec/policy.hpp"
#include "unisph/solver/case_file.hpp"
#include "unisph/solver/solver_checkpoint.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"

#if UNISPH_HAS_CUDA
#include <cuda_runtime.h>
#endif

#ifndef UNISPH_SOURCE_CASES_DIR
#define UNISPH_SOURCE_CASES_DIR "cases"
#endif

namespace {

using namespace unisph;
namespace fs = std::filesystem;

struct Settings {
  fs::path cache;
  fs::path cases;
  std::uint64_t steps = 1000;
  double checkpoint_time = 6;
};
Settings settings;

struct Config {
  std::string case_file;  // in the cases folder
  int dimension;
  double dx;           // in units of H
  std::string dx_name; // "H_40", "0.025"
  bool single;
  PolicyKind policy;
  double estimated_particles;
  bool moving_wall_family = false;  // SphMovingWall
  bool at_rest = false;             // SphMovingWall: the paddle's motion removed
};

std::string policy_label(PolicyKind k) { return k == PolicyKind::device ? "gpu" : std::string(to_string(k)); }

std::size_t device_free_bytes() {
#if UNISPH_HAS_CUDA
  std::size_t free = 0, total = 0;
  if (cudaMemGetInfo(&free, &total) == cudaSuccess) return free;
#endif
  return 0;
}

sph::CaseDescription description_of(const Config& c) {
  sph::CaseDescription d = sph::read_case_file((settings.cases / c.case_file).string());
  d.dx = c.dx * d.length_scale;
  return d;
}

// In the child process: runs the case from t = 0 to the checkpoint time on the fastest policy
// here (the state is the same on every policy, to round-off) and writes the checkpoint.
template <class T, int D>
void make_checkpoint(const sph::CaseDescription& d, const fs::path& file) {
  const auto start = std::chrono::steady_clock::now();
  sph::WeaklyCompressibleSolver<T, D> solver(d, execution_info().available.back());
  const double until = settings.checkpoint_time * d.time_scale;
  while (solver.time() < until * (1 - 1e-12)) solver.advance(until);
  solver.write_checkpoint(file);
  std::fprintf(stderr, "sph_bench: made %s on %s (%llu acoustic steps, %.1f s)\n", file.string().c_str(),
               policy_label(execution_info().available.back()).c_str(), (unsigned long long)solver.acoustic_steps(),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

// "D:dx:precision:case:file" (dx in units of H; case: the case file's name in the cases folder).
int make_checkpoint_from(const std::string& spec) {
  try {
    const std::size_t a = spec.find(':'), b = spec.find(':', a + 1), c = spec.find(':', b + 1),
                      e = c == std::string::npos ? c : spec.find(':', c + 1);
    if (a == std::string::npos || b == std::string::npos || c == std::string::npos || e == std::string::npos)
      throw Error("--sph_make=" + spec + ": expected D:dx:precision:case:file");
    Config config{spec.substr(c + 1, e - c - 1), std::stoi(spec.substr(0, a)), std::stod(spec.substr(a + 1, b - a - 1)), "",
                  spec.substr(b + 1, c - b - 1) == "float", PolicyKind::seq, 0};
    const fs::path file = spec.substr(e + 1);
    const sph::CaseDescription d = description_of(config);
    if (config.dimension == 2)
      config.single ? make_checkpoint<float, 2>(d, file) : make_checkpoint<double, 2>(d, file);
    else
      config.single ? make_checkpoint<float, 3>(d, file) : make_checkpoint<double, 3>(d, file);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sph_bench: %s\n", e.what());
    return 1;
  }
}

template <class T, int D>
fs::path checkpoint_for(const Config& c, const sph::CaseDescription& d) {
  char name[160];
  std::snprintf(name, sizeof name, "%s_dx%s_%s_t%g.bin", fs::path(c.case_file).stem().c_str(), c.dx_name.c_str(),
                c.single ? "float" : "double", settings.checkpoint_time);
  const fs::path file = settings.cache / name;
  if (fs::exists(file)) {
    // A cached checkpoint of an older version of the case file, or of an older checkpoint
    // format (refused by the reader), is made again.
    std::string difference;
    try {
      difference = sph::physics_difference(d, sph::read_checkpoint_summary(file).description);
    } catch (const io::CheckpointError& e) {
      difference = e.what();
    }
    if (difference.empty()) return file;
    std::fprintf(stderr, "sph_bench: %s is for another case or format (%s); making it again\n", file.string().c_str(),
                 difference.c_str());
  }
  fs::create_directories(settings.cache);
  // Made by a child process, so that the device memory it takes (the runtime's scratch buffer
  // is kept for the life of a process) does not hide in the free memory measured here.
  char dx[64];
  std::snprintf(dx, sizeof dx, "%.17g", c.dx);
  const std::string command = "'" + fs::read_symlink("/proc/self/exe").string() + "' '--sph_make=" + std::to_string(D) + ":" + dx + ":" +
                              (c.single ? "float" : "double") + ":" + c.case_file + ":" + file.string() + "' '--sph_cases=" +
                              settings.cases.string() + "' '--sph_checkpoint_time=" +
                              std::to_string(settings.checkpoint_time) + "'";
  if (std::system(command.c_str()) != 0 || !fs::exists(file))
    throw Error("sph_bench: making the checkpoint " + file.string() + " failed (" + command + ")");
  return file;
}

template <class T, int D>
void run_dam_break_checked(benchmark::State& state, const Config& c);

// A moving wall's cost: the flume from t = 0, with its paddle moving or held at rest.
template <class T, int D>
void run_moving_wall(benchmark::State& state, const Config& c) {
  try {
    sph::CaseDescription d = description_of(c);
    if (c.at_rest)
      for (auto& body : d.bodies) body.translation = {}, body.rotation = {};
    sph::WeaklyCompressibleSolver<T, D> solver(d, c.policy, /*settle=*/false);
    solver.advance(1e300);  // warm-up step (copies to the device, first allocations): not timed
    const std::uint64_t acoustic0 = solver.acoustic_steps(), advection0 = solver.advection_steps();
    double seconds = 0;
    for (auto _ : state) {
      const auto start = std::chrono::steady_clock::now();
      while (solver.acoustic_steps() - acoustic0 < settings.steps) solver.advance(1e300);
      solver.observe();
      seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      state.SetIterationTime(seconds);
    }
    const double acoustic = double(solver.acoustic_steps() - acoustic0), fluid = double(solver.fluid_count());
    state.counters["fluid_particles"] = fluid;
    state.counters["wall_particles"] = double(solver.wall_count());
    state.counters["acoustic_steps"] = acoustic;
    state.counters["advection_steps"] = double(solver.advection_steps() - advection0);
    state.counters["fluid_steps_per_s"] = acoustic * fluid / seconds;
    state.counters["seconds_per_acoustic_step"] = seconds / acoustic;
    state.SetLabel(c.case_file + " 2D dx " + c.dx_name + (c.at_rest ? " paddle at rest " : " paddle moving ") +
                   (c.single ? "float" : "double") + " " + policy_label(c.policy) +
                   (c.policy == PolicyKind::par ? " (" + std::to_string(host_threads()) + " threads)" : ""));
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
}

template <class T, int D>
void run_dam_break(benchmark::State& state, const Config& c) {
  try {
    run_dam_break_checked<T, D>(state, c);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
}

template <class T, int D>
void run_dam_break_checked(benchmark::State& state, const Config& c) {
  const sph::CaseDescription d = description_of(c);
  const fs::path checkpoint = checkpoint_for<T, D>(c, d);
  const bool device = c.policy == PolicyKind::device;
  const std::size_t free_before = device ? device_free_bytes() : 0;
  std::size_t free_least = free_before;
  auto sample = [&] {
    if (device) free_least = std::min(free_least, device_free_bytes());
  };

  sph::WeaklyCompressibleSolver<T, D> solver(d, c.policy, /*settle=*/false);  // the checkpoint holds the state
  solver.restore_checkpoint(checkpoint);
  const double t_star_restart = solver.time() / d.time_scale;
  solver.advance(1e300);  // warm-up step (copies to the device, first allocations): not timed
  sample();
  const std::uint64_t acoustic0 = solver.acoustic_steps(), advection0 = solver.advection_steps();
  double seconds = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    while (solver.acoustic_steps() - acoustic0 < settings.steps) solver.advance(1e300);
    solver.observe();  // waits for the device (a reduction), and is what a run does anyway
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.SetIterationTime(seconds);
  }
  sample();
  const double acoustic = double(solver.acoustic_steps() - acoustic0);
  const double fluid = double(solver.fluid_count()), wall = double(solver.wall_count());

  // The momentum kernel alone: repeated passes over the state reached, at least 0.2 s of them.
  solver.pressure_relaxation_pass();
  int passes = 0;
  const auto pass_start = std::chrono::steady_clock::now();
  double pass_seconds = 0;
  do {
    solver.pressure_relaxation_pass();
    ++passes;
    pass_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - pass_start).count();
  } while (pass_seconds < 0.2 && passes < 1000);
  const double pass = pass_seconds / passes;
  const sph::PairCounts pairs = solver.count_pairs();
  sample();

  state.counters["fluid_particles"] = fluid;
  state.counters["wall_particles"] = wall;
  state.counters["acoustic_steps"] = acoustic;
  state.counters["advection_steps"] = double(solver.advection_steps() - advection0);
  state.counters["t_star_restart"] = t_star_restart;
  state.counters["fluid_steps_per_s"] = acoustic * fluid / seconds;
  state.counters["pressure_relaxation_ms"] = pass * 1e3;
  state.counters["pressure_relaxation_ms_per_1e6"] = pass * 1e3 / (fluid / 1e6);
  state.counters["candidate_pairs"] = double(pairs.candidate_pairs);
  state.counters["neighbor_pairs"] = double(pairs.neighbor_pairs);
  state.counters["candidate_pairs_per_s"] = double(pairs.candidate_pairs) / pass;
  state.counters["neighbor_pairs_per_s"] = double(pairs.neighbor_pairs) / pass;
  state.counters["neighbors_per_fluid_particle"] = double(pairs.neighbor_pairs) / fluid;
  state.counters["device_bytes_per_particle"] = device ? double(free_before - free_least) / (fluid + wall) : 0.0;
  state.SetLabel(c.case_file + " " + std::string(D == 2 ? "2D" : "3D") + " dx " + c.dx_name + " " + (c.single ? "float" : "double") + " " +
                 policy_label(c.policy) + (c.policy == PolicyKind::par ? " (" + std::to_string(host_threads()) + " threads)" : ""));
}

void register_all() {
  std::vector<Config> configs;
  for (int n : {40, 80, 160, 320})
    for (bool single : {true, false})
      for (PolicyKind k : execution_info().available)
        configs.push_back({"dambreak_2d.toml", 2, 1.0 / n, "H_" + std::to_string(n), single, k, 2.0 * n * n});
  const char* names3[] = {"0.05", "0.025", "0.0125", "0.00625"};
  const double dx3[] = {0.05, 0.025, 0.0125, 0.00625};
  for (const char* file : {"dambreak_3d.toml", "dambreak_general_3d.toml", "dambreak_stl_3d.toml"})
    for (int s = 0; s < 4; ++s)
      for (bool single : {true, false})
        for (PolicyKind k : execution_info().available)
          configs.push_back({file, 3, dx3[s], names3[s], single, k, 1.0 / (dx3[s] * dx3[s] * dx3[s])});
  for (const char* dx : {"0.02", "0.01"})
    for (bool at_rest : {false, true})
      for (bool single : {true, false})
        for (PolicyKind k : execution_info().available) {
          const double spacing = std::stod(dx);
          configs.push_back({"piston_flume_2d.toml", 2, spacing, dx, single, k, 30.0 / (spacing * spacing), true, at_rest});
        }
  // Ascending particle count (float before double): the device's kept scratch storage then
  // only grows, and the quick cases come first.
  std::stable_sort(configs.begin(), configs.end(),
                   [](const Config& a, const Config& b) { return a.estimated_particles < b.estimated_particles; });
  for (const Config& c : configs) {
    if (c.moving_wall_family) {
      const std::string name = std::string("SphMovingWall/2D/") + c.dx_name + "/" + (c.at_rest ? "at_rest/" : "moving/") +
                               (c.single ? "float/" : "double/") + policy_label(c.policy);
      benchmark::internal::Benchmark* b = c.single ? benchmark::RegisterBenchmark(name.c_str(), run_moving_wall<float, 2>, c)
                                                   : benchmark::RegisterBenchmark(name.c_str(), run_moving_wall<double, 2>, c);
      b->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
      continue;
    }
    const std::string form = c.case_file == "dambreak_general_3d.toml" ? "General" : c.case_file == "dambreak_stl_3d.toml" ? "Stl" : "";
    const std::string name = "SphDamBreak" + form + "/" + (c.dimension == 2 ? "2D/" : "3D/") + c.dx_name + "/" +
                             (c.single ? "float/" : "double/") + policy_label(c.policy);
    benchmark::internal::Benchmark* b;
    if (c.dimension == 2)
      b = c.single ? benchmark::RegisterBenchmark(name.c_str(), run_dam_break<float, 2>, c)
                   : benchmark::RegisterBenchmark(name.c_str(), run_dam_break<double, 2>, c);
    else
      b = c.single ? benchmark::RegisterBenchmark(name.c_str(), run_dam_break<float, 3>, c)
                   : benchmark::RegisterBenchmark(name.c_str(), run_dam_break<double, 3>, c);
    b->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
  }
}

fs::path default_cache() {
  if (const char* e = std::getenv("UNISPH_SPH_BENCH_CACHE"); e && *e) return e;
  if (const char* e = std::getenv("XDG_CACHE_HOME"); e && *e) return fs::path(e) / "unisph" / "sph_bench";
  if (const char* e = std::getenv("HOME"); e && *e) return fs::path(e) / ".cache" / "unisph" / "sph_bench";
  return "sph_bench_cache";
}

fs::path default_cases() {
  if (const char* e = std::getenv("UNISPH_CASES_DIR"); e && *e) return e;
  if (fs::exists("cases/dambreak_2d.toml")) return "cases";
  return UNISPH_SOURCE_CASES_DIR;
}

std::string machine() {
  std::string cpu;
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);)
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  return std::string(host) + ", " + cpu + ", " + std::to_string(host_threads()) + " threads";
}

}  // namespace

int main(int argc, char** argv) {
  settings.cache = default_cache();
  settings.cases = default_cases();
  std::vector<char*> rest;
  std::string make;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char* key) -> const char* {
      const std::string k = std::string(key) + "=";
      return a.rfind(k, 0) == 0 ? argv[i] + k.size() : nullptr;
    };
    if (const char* v = value("--sph_cache")) settings.cache = v;
    else if (const char* v = value("--sph_cases")) settings.cases = v;
    else if (const char* v = value("--sph_steps")) settings.steps = std::strtoull(v, nullptr, 10);
    else if (const char* v = value("--sph_checkpoint_time")) settings.checkpoint_time = std::strtod(v, nullptr);
    else if (const char* v = value("--sph_make")) make = v;
    else rest.push_back(argv[i]);
  }
  if (!make.empty()) return make_checkpoint_from(make);
  int rest_count = int(rest.size());
  benchmark::Initialize(&rest_count, rest.data());
  if (benchmark::ReportUnrecognizedArguments(rest_count, rest.data())) return 1;
  register_all();
  benchmark::AddCustomContext("machine", machine());
  benchmark::AddCustomContext("device", execution_info().device_present ? execution_info().device_name
                                                                        : "absent: " + execution_info().device_unavailable_reason);
  benchmark::AddCustomContext("checkpoint_cache", settings.cache.string());
  benchmark::AddCustomContext("timed_acoustic_steps", std::to_string(settings.steps));
  benchmark::AddCustomContext("checkpoint_t_star", std::to_string(settings.checkpoint_time));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
