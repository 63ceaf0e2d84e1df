// Hierarchical views (iter::View) against hand-written loops over the same supercells:
//   all_particles   every particle of every supercell
//   strided         every second frame of each supercell, and in it the slots 1, 4, 7, ...
// Three loops: "view" is the slides' iterator loop (a range-for over the view), "for_each" the
// view's internal iteration (View::for_each: one plain loop per level), "hand" the loop one
// writes without views. Each sums x * w over the particles it visits. Both loops of a pair must produce the same
// checksum (the values are small integers, so the sums are exact in any order); the checksum is
// reported as a counter.
//
//   <case>/<loop>/<policy>   policy seq, par: one supercell per item of particle_for (oneTBB shares
//                            the supercells among the cores); device: the same on the GPU, one
//                            thread per supercell; each item stores its supercell's sum
//   <case>/<loop>/team       GPU: one block of 256 threads per supercell, the particles of each frame
//                            shared through the block (collective_for, collectivity::DeviceBlock);
//                            each thread stores its partial sum
// The checksum (the sum of the stored sums) is added up on the host after the timed loop.
//
// scripts/views_bench_report.py turns --benchmark_format=json output (with
// --benchmark_repetitions=20) into the table of medians and ratios in docs/views.md.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>
#include <vector>

#include "unisph/iter/iter.hpp"
#include "unisph/unisph.hpp"

namespace {
using namespace unisph;
using iter::all;
using iter::RuntimeTuple;
namespace direction = iter::direction;
namespace collectivity = iter::collectivity;

struct BenchParticle {
  double x, w;
};
constexpr Index slots = 256;
using BenchFrame = iter::Frame<BenchParticle, slots>;
using ConstFrame = const BenchFrame;
using Cells = iter::Supercells<ConstFrame>;
constexpr Index supercell_count = 8192;

// 8192 supercells of 200..1799 particles (about 8.2 million, 131 MB), frames of a supercell
// adjacent in the pool, as after a sort.
iter::SupercellContainer<BenchParticle, slots>& supercells() {
  static iter::SupercellContainer<BenchParticle, slots> container("bench", supercell_count);
  static bool filled = false;
  if (!filled) {
    std::uint64_t state = 12345, id = 0;
    std::vector<BenchParticle> particles;
    for (Index c = 0; c < supercell_count; ++c) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      const Index n = 200 + (state >> 33) % 1600;
      particles.clear();
      for (Index p = 0; p < n; ++p, ++id) particles.push_back({double(id % 1000), double(id % 7 + 1)});
      container.append(c, particles);
    }
    filled = true;
  }
  return container;
}

// The body of every loop: adds x * w of a valid slot.
struct Accumulate {
  double& sum;
  UNISPH_HOST_DEVICE void operator()(iter::SlotRef<const BenchParticle> slot) const {
    if (slot) sum += slot->x * slot->w;
  }
};

// The view loops come in two forms: the slides' iterator loop (a range-for) and View::for_each.
template <bool ForEach, class View>
UNISPH_HOST_DEVICE double sum_over(const View& view) {
  double sum = 0;
  const Accumulate add{sum};
  if constexpr (ForEach)
    view.for_each(add);
  else
    for (auto slot : view) add(slot);
  return sum;
}

// ---- (a) all particles ------------------------------------------------------------------------

template <bool ForEach>
struct AllView {
  Cells cells;
  UNISPH_HOST_DEVICE double operator()(Index c) const {
    using Particles = iter::View<ConstFrame, direction::Forward, collectivity::None, iter::CompileTimeTuple<>>;
    const iter::View<iter::Supercell<ConstFrame>, direction::Forward, collectivity::None, iter::CompileTimeTuple<>, Particles>
        view(cells[c]);
    return sum_over<ForEach>(view);
  }
};

struct AllHand {
  Cells cells;
  UNISPH_HOST_DEVICE double operator()(Index c) const {
    const iter::SupercellHeader h = cells.headers[c];
    double sum = 0;
    for (Index f = h.first_frame; f != iter::no_frame; f = cells.frames[f].next) {
      const Index n = f == h.last_frame ? h.particles_in_last_frame : slots;
      const BenchParticle* p = cells.frames[f].slots;
      for (Index s = 0; s < n; ++s) sum += p[s].x * p[s].w;
    }
    return sum;
  }
};

// ---- (b) a strided subset: every second frame, slots 1, 4, 7, ... -------------------------------

constexpr Index frame_jump = 2, slot_offset = 1, slot_jump = 3;

template <bool ForEach>
struct StridedView {
  Cells cells;
  UNISPH_HOST_DEVICE double operator()(Index c) const {
    using Particles = iter::View<ConstFrame, direction::Forward, collectivity::None, RuntimeTuple>;
    const iter::View<iter::Supercell<ConstFrame>, direction::Forward, collectivity::None, RuntimeTuple, Particles> view(
        cells[c], RuntimeTuple{0, all, frame_jump}, Particles(nullptr, RuntimeTuple{slot_offset, all, slot_jump}));
    return sum_over<ForEach>(view);
  }
};

struct StridedHand {
  Cells cells;
  UNISPH_HOST_DEVICE double operator()(Index c) const {
    const iter::SupercellHeader h = cells.headers[c];
    double sum = 0;
    Index k = 0;
    for (Index f = h.first_frame; f != iter::no_frame; f = cells.frames[f].next, ++k) {
      if (k % frame_jump != 0) continue;
      const Index n = f == h.last_frame ? h.particles_in_last_frame : slots;
      const BenchParticle* p = cells.frames[f].slots;
      for (Index s = slot_offset; s < n; s += slot_jump) sum += p[s].x * p[s].w;
    }
    return sum;
  }
};

// ---- the same per team (GPU blocks of 256 threads) --------------------------------------------

constexpr Index team_size = 256;

template <bool Strided, bool ForEach>
struct TeamView {
  Cells cells;
  unisph::View<double> partial;  // team_size per supercell
  template <class Team>
  UNISPH_HOST_DEVICE void operator()(const Team& team, Index c) const {
    using Particles = iter::View<ConstFrame, direction::Forward, Team, RuntimeTuple>;
    const RuntimeTuple frames{0, all, Strided ? frame_jump : 1};
    const RuntimeTuple particles{Strided ? slot_offset : 0, all, Strided ? slot_jump : 1};
    const iter::View<iter::Supercell<ConstFrame>, direction::Forward, collectivity::None, RuntimeTuple, Particles> view(
        cells[c], frames, Particles(nullptr, particles, iter::NoChild{}, team));
    partial[c * team_size + team.rank()] = sum_over<ForEach>(view);
  }
};

template <bool Strided>
struct TeamHand {
  Cells cells;
  unisph::View<double> partial;
  template <class Team>
  UNISPH_HOST_DEVICE void operator()(const Team& team, Index c) const {
    const iter::SupercellHeader h = cells.headers[c];
    const Index first_slot = (Strided ? slot_offset : 0) + team.rank() * (Strided ? slot_jump : 1);
    const Index step = team.size() * (Strided ? slot_jump : 1);
    double sum = 0;
    Index k = 0;
    for (Index f = h.first_frame; f != iter::no_frame; f = cells.frames[f].next, ++k) {
      if (Strided && k % frame_jump != 0) continue;
      const Index n = f == h.last_frame ? h.particles_in_last_frame : slots;
      const BenchParticle* p = cells.frames[f].slots;
      for (Index s = first_slot; s < n; s += step) sum += p[s].x * p[s].w;
    }
    partial[c * team_size + team.rank()] = sum;
  }
};

template <class P>
bool skip_unavailable(benchmark::State& state) {
  if (P::space == MemorySpace::device && !policy_available(PolicyKind::device)) {
    state.SkipWithError(execution_info().device_unavailable_reason.c_str());
    return true;
  }
  return false;
}

// One supercell per item of particle_for; each item stores its supercell's sum. The checksum is
// added up on the host after the timed loop, the same way for every policy.
template <class Kernel>
struct StoreSum {
  Kernel loop;
  unisph::View<double> sums;
  UNISPH_HOST_DEVICE void operator()(Index c) const { sums[c] = loop(c); }
};

double host_total(DiscreteVariable<double>& values) {
  double total = 0;
  for (double v : values.to_vector()) total += v;
  return total;
}

template <class P, class Kernel>
void PerSupercell(benchmark::State& state) {
  if (skip_unavailable<P>(state)) return;
  DiscreteVariable<double> sums("sums", supercell_count);
  const StoreSum<Kernel> kernel{Kernel{supercells().read(P{})}, sums.write(P{})};
  particle_for(P{}, supercell_count, kernel);  // warm-up
  fence(P{});
  for (auto _ : state) {
    particle_for(P{}, supercell_count, kernel);
    fence(P{});
  }
  state.counters["checksum"] = host_total(sums);
  state.counters["frames"] = double(supercells().frame_count());
  state.SetLabel("policy=" + std::string(P::name));
}

template <class Kernel>
void PerTeam(benchmark::State& state) {
  using P = ParallelDevicePolicy;
  if (skip_unavailable<P>(state)) return;
  DiscreteVariable<double> partial("partial", supercell_count * team_size);
  const Kernel kernel{supercells().read(P{}), partial.write(P{})};
  iter::collective_for(P{}, supercell_count, team_size, kernel);  // warm-up
  fence(P{});
  for (auto _ : state) {
    iter::collective_for(P{}, supercell_count, team_size, kernel);
    fence(P{});
  }
  state.counters["checksum"] = host_total(partial);
  state.SetLabel("policy=device, one block of 256 per supercell");
}

#define UNISPH_VIEWS_BENCHMARK(CASE, LOOP, ...) \
  BENCHMARK_TEMPLATE(__VA_ARGS__)->Name(CASE "/" LOOP)->UseRealTime()->Unit(benchmark::kMillisecond);
#define UNISPH_VIEWS_BENCHMARKS(P, policy_name)                                                  \
  UNISPH_VIEWS_BENCHMARK("all_particles", "view/" policy_name, PerSupercell, P, AllView<false>)     \
  UNISPH_VIEWS_BENCHMARK("all_particles", "for_each/" policy_name, PerSupercell, P, AllView<true>)  \
  UNISPH_VIEWS_BENCHMARK("all_particles", "hand/" policy_name, PerSupercell, P, AllHand)            \
  UNISPH_VIEWS_BENCHMARK("strided", "view/" policy_name, PerSupercell, P, StridedView<false>)       \
  UNISPH_VIEWS_BENCHMARK("strided", "for_each/" policy_name, PerSupercell, P, StridedView<true>)    \
  UNISPH_VIEWS_BENCHMARK("strided", "hand/" policy_name, PerSupercell, P, StridedHand)

UNISPH_VIEWS_BENCHMARKS(SequencedPolicy, "seq")
UNISPH_VIEWS_BENCHMARKS(ParallelPolicy, "par")
#if UNISPH_HAS_CUDA && defined(__CUDACC__)
UNISPH_VIEWS_BENCHMARKS(ParallelDevicePolicy, "device")
UNISPH_VIEWS_BENCHMARK("all_particles", "view/team", PerTeam, TeamView<false, false>)
UNISPH_VIEWS_BENCHMARK("all_particles", "for_each/team", PerTeam, TeamView<false, true>)
UNISPH_VIEWS_BENCHMARK("all_particles", "hand/team", PerTeam, TeamHand<false>)
UNISPH_VIEWS_BENCHMARK("strided", "view/team", PerTeam, TeamView<true, false>)
UNISPH_VIEWS_BENCHMARK("strided", "for_each/team", PerTeam, TeamView<true, true>)
UNISPH_VIEWS_BENCHMARK("strided", "hand/team", PerTeam, TeamHand<true>)
#endif

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  const ExecutionInfo& info = execution_info();
  benchmark::AddCustomContext("unisph_host_threads", std::to_string(host_threads()));
  benchmark::AddCustomContext("unisph_gpu", policy_available(PolicyKind::device) ? info.device_name
                                                                                 : info.device_unavailable_reason);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
