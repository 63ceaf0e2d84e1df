// Benchmarks of the execution core on every policy this build has:
//   Triad           a = b + s c via particle_for          GB/s (bytes read + written: 3 N sizeof(Real))
//   Reduce          sum of a via particle_reduce           GB/s (N sizeof(Real) read)
//   DeterministicReduce  the same via deterministic_reduce (one association on every policy)
//   Scan            exclusive_scan of uint32               items/s (and GB/s: 2 N 4 bytes)
//   SortPairs       sort_pairs of uint32 keys + values     keys/s
// and the references they are judged against, measured in the same run:
//   DeviceMemcpy    cudaMemcpy device to device of B bytes counted as 2B (read + write)
//   CubSortPairs    cub::DeviceRadixSort::SortPairs called directly, temporary storage reused
//   TwoThreadTriad  the triad on two plain std::threads (the CI machine has 2 cores)
//   ParTriadAgainstTwoThreads  par and the two threads alternately on the same arrays, paired
//                   per iteration, so that the ratio does not depend on the bandwidth drift of
//                   a shared machine between two separate benchmarks
//   Compute         64 dependent fused multiply-adds per item, seq vs par
// Output: --benchmark_format=json; scripts/exec_bench_report.py turns it into the table in
// docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "unisph/unisph.hpp"

#if UNISPH_HAS_CUDA && defined(__CUDACC__)
#include <cub/device/device_radix_sort.cuh>
#endif

namespace {
using namespace unisph;

std::string precision() { return sizeof(Real) == 8 ? "double" : "float"; }

template <class P>
bool skip_unavailable(benchmark::State& state) {
  if (!policy_available(P::space == MemorySpace::device ? PolicyKind::device : PolicyKind::seq)) {
    state.SkipWithError(execution_info().device_unavailable_reason.c_str());
    return true;
  }
  return false;
}

template <class P>
void label(benchmark::State& state) {
  state.SetLabel("policy=" + std::string(P::name) + " precision=" + precision() + " N=" + std::to_string(state.range(0)));
}

struct TriadKernel {
  View<Real> a;
  View<const Real> b, c;
  Real scale;
  UNISPH_HOST_DEVICE void operator()(Index i) const { a[i] = b[i] + scale * c[i]; }
};

struct ValueOf {
  View<const Real> v;
  UNISPH_HOST_DEVICE Real operator()(Index i) const { return v[i]; }
};

void fill(DiscreteVariable<Real>& v, Real offset) {
  View<Real> h = v.write(MemorySpace::host);
  for (Index i = 0; i < h.size(); ++i) h[i] = offset + Real(i % 1024) * Real(0.25);
}

template <class P>
void Triad(benchmark::State& state) {
  if (skip_unavailable<P>(state)) return;
  const Index n = static_cast<Index>(state.range(0));
  DiscreteVariable<Real> a("a", n), b("b", n), c("c", n);
  fill(b, 1), fill(c, 2);
  const TriadKernel kernel{a.write(P{}), b.read(P{}), c.read(P{}), Real(3)};
  particle_for(P{}, n, kernel);
  fence(P{});
  for (auto _ : state) {
    particle_for(P{}, n, kernel);
    fence(P{});
  }
  state.SetBytesProcessed(state.iterations() * int64_t(3 * n * sizeof(Real)));
  label<P>(state);
}

template <class P>
void Reduce(benchmark::State& state) {
  if (skip_unavailable<P>(state)) return;
  const Index n = static_cast<Index>(state.range(0));
  DiscreteVariable<Real> a("a", n);
  fill(a, 1);
  const ValueOf f{a.read(P{})};
  // The result goes to a volatile sink rather than through benchmark::DoNotOptimize(double&):
  // with GCC that can hand back a wrong value (google/benchmark#903, GCC PR 92597).
  volatile Real sink = 0;
  for (auto _ : state) sink = particle_reduce(P{}, n, Sum<Real>{}, f);  // a host value: includes the wait
  (void)sink;
  state.SetBytesProcessed(state.iterations() * int64_t(n * sizeof(Real)));
  label<P>(state);
}

template <class P>
void DeterministicReduce(benchmark::State& state) {
  if (skip_unavailable<P>(state)) return;
  const Index n = static_cast<Index>(state.range(0));
  DiscreteVariable<Real> a("a", n);
  fill(a, 1);
  const ValueOf f{a.read(P{})};
  volatile Real sink = 0;
  for (auto _ : state) sink = deterministic_reduce(P{}, n, Sum<Real>{}, f);  // a host value: includes the wait
  (void)sink;
  state.SetBytesProcessed(state.iterations() * int64_t(n * sizeof(Real)));
  label<P>(state);
}

template <class P>
void Scan(benchmark::State& state) {
  if (skip_unavailable<P>(state)) return;
  const Index n = static_cast<Index>(state.range(0));
  DiscreteVariable<std::uint32_t> in("in", n), out("out", n);
  {
    View<std::uint32_t> h = in.write(MemorySpace::host);
    for (Index i = 0; i < n; ++i) h[i] = static_cast<std::uint32_t>(i % 7);
  }
  const View<const std::uint32_t> input = in.read(P{});
  const View<std::uint32_t> output = out.write(P{});
  for (auto _ : state) {
    exclusive_scan(P{}, input, output);
    fence(P{});
  }
  state.SetItemsProcessed(state.iterations() * int64_t(n));
  state.SetBytesProcessed(state.iterations() * int64_t(2 * n * sizeof(std::uint32_t)));
  label<P>(state);
}

// Random 32-bit keys with their indices as values; each repetition sorts a fresh copy (the copy
// is not timed).
struct SortInput {
  DiscreteVariable<std::uint32_t> pristine_keys{"pristine keys"}, keys{"keys"}, values{"values"},
      indices{"indices"};
  explicit SortInput(Index n) {
    std::vector<std::uint32_t> k(n), v(n);
    std::mt19937 rng(7);
    for (Index i = 0; i < n; ++i) k[i] = static_cast<std::uint32_t>(rng()), v[i] = static_cast<std::uint32_t>(i);
    pristine_keys.assign(k);
    indices.assign(v);
    keys.resize(n);
    values.resize(n);
  }
};

struct CopyPairs {
  View<const std::uint32_t> from_keys, from_values;
  View<std::uint32_t> to_keys, to_values;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    to_keys[i] = from_keys[i];
    to_values[i] = from_values[i];
  }
};

template <class P>
void SortPairs(benchmark::State& state) {
  if (skip_unavailable<P>(state)) return;
  const Index n = static_cast<Index>(state.range(0));
  SortInput input(n);
  const CopyPairs reset{input.pristine_keys.read(P{}), input.indices.read(P{}), input.keys.write(P{}),
                        input.values.write(P{})};
  const View<std::uint32_t> keys = input.keys.read_write(P{}), values = input.values.read_write(P{});
  for (auto _ : state) {
    particle_for(P{}, n, reset);
    fence(P{});
    const auto start = std::chrono::steady_clock::now();
    sort_pairs(P{}, keys, values);
    fence(P{});
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  state.SetItemsProcessed(state.iterations() * int64_t(n));
  label<P>(state);
}

// --- References -------------------------------------------------------------------------------

void TwoThreadTriad(benchmark::State& state) {
  const Index n = static_cast<Index>(state.range(0));
  DiscreteVariable<Real> a("a", n), b("b", n), c("c", n);
  fill(b, 1), fill(c, 2);
  const TriadKernel kernel{a.write(seq), b.read(seq), c.read(seq), Real(3)};
  // Each thread gets its own copy of the kernel (as every policy's launch does), so the
  // compiler sees the same loop it sees in par.
  auto half = [kernel](Index begin, Index end) {
    for (Index i = begin; i < end; ++i) kernel(i);
  };
  for (auto _ : state) {
    std::thread first(half, Index(0), n / 2), second(half, n / 2, n);
    first.join();
    second.join();
  }
  state.SetBytesProcessed(state.iterations() * int64_t(3 * n * sizeof(Real)));
  state.SetLabel("two std::threads precision=" + precision() + " N=" + std::to_string(n));
}

// Paired measurement: each iteration times the par triad and the two-thread triad back to back
// (which one goes first alternates), on the same arrays. Reports both bandwidths over the
// whole run and the median of the per-iteration ratios (par throughput / two-thread throughput).
void ParTriadAgainstTwoThreads(benchmark::State& state) {
  const Index n = static_cast<Index>(state.range(0));
  DiscreteVariable<Real> a("a", n), b("b", n), c("c", n);
  fill(b, 1), fill(c, 2);
  const TriadKernel kernel{a.write(par), b.read(par), c.read(par), Real(3)};
  auto half = [kernel](Index begin, Index end) {
    for (Index i = begin; i < end; ++i) kernel(i);
  };
  auto run_par = [&] { particle_for(par, n, kernel); };
  auto run_threads = [&] {
    std::thread first(half, Index(0), n / 2), second(half, n / 2, n);
    first.join();
    second.join();
  };
  using clock = std::chrono::steady_clock;
  auto seconds_of = [](auto&& f) {
    const auto start = clock::now();
    f();
    return std::chrono::duration<double>(clock::now() - start).count();
  };
  run_par(), run_threads();  // first touch and warm-up
  double par_total = 0, threads_total = 0;
  std::vector<double> ratios;
  bool par_first = true;
  for (auto _ : state) {
    double t_par, t_threads;
    if (par_first) {
      t_par = seconds_of(run_par);
      t_threads = seconds_of(run_threads);
    } else {
      t_threads = seconds_of(run_threads);
      t_par = seconds_of(run_par);
    }
    par_first = !par_first;
    par_total += t_par, threads_total += t_threads;
    ratios.push_back(t_threads / t_par);
    state.SetIterationTime(t_par);
  }
  std::sort(ratios.begin(), ratios.end());
  const double bytes = double(state.iterations()) * 3.0 * double(n) * sizeof(Real);
  state.counters["par_GBps"] = bytes / par_total * 1e-9;
  state.counters["two_threads_GBps"] = bytes / threads_total * 1e-9;
  state.counters["par_over_two_threads"] = threads_total / par_total;
  state.counters["median_pair_ratio"] = ratios.empty() ? 0.0 : ratios[ratios.size() / 2];
  state.SetBytesProcessed(state.iterations() * int64_t(3 * n * sizeof(Real)));
  state.SetLabel("par vs two std::threads, paired, precision=" + precision() + " N=" + std::to_string(n));
}

struct ComputeKernel {
  View<const Real> in;
  View<Real> out;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    Real x = in[i];
    for (int k = 0; k < 64; ++k) x = x * Real(0.999) + Real(0.001);  // 64 dependent multiply-adds
    out[i] = x;
  }
};

template <class P>
void Compute(benchmark::State& state) {
  if (skip_unavailable<P>(state)) return;
  const Index n = static_cast<Index>(state.range(0));
  DiscreteVariable<Real> in("in", n), out("out", n);
  fill(in, 1);
  const ComputeKernel kernel{in.read(P{}), out.write(P{})};
  for (auto _ : state) {
    particle_for(P{}, n, kernel);
    fence(P{});
  }
  state.SetItemsProcessed(state.iterations() * int64_t(n));
  state.counters["FMA/s"] = benchmark::Counter(double(state.iterations()) * double(n) * 64.0, benchmark::Counter::kIsRate);
  label<P>(state);
}

#if UNISPH_HAS_CUDA && defined(__CUDACC__)
void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) throw DeviceError(std::string(what) + ": " + cudaGetErrorString(e));
}

// B bytes copied device to device move 2B (read + write).
void DeviceMemcpy(benchmark::State& state) {
  if (skip_unavailable<ParallelDevicePolicy>(state)) return;
  const Index n = static_cast<Index>(state.range(0));
  DiscreteVariable<Real> a("a", n), b("b", n);
  fill(b, 1);
  Real* to = a.write(par_device).data();
  const Real* from = b.read(par_device).data();
  cudaStream_t stream = static_cast<cudaStream_t>(unisph::cuda::stream_handle());
  for (auto _ : state) {
    check(cudaMemcpyAsync(to, from, n * sizeof(Real), cudaMemcpyDeviceToDevice, stream), "memcpy");
    check(cudaStreamSynchronize(stream), "memcpy");
  }
  state.SetBytesProcessed(state.iterations() * int64_t(2 * n * sizeof(Real)));
  state.SetLabel("cudaMemcpy device to device, counted read + write, N=" + std::to_string(n) + " " + precision());
}

void CubSortPairs(benchmark::State& state) {
  if (skip_unavailable<ParallelDevicePolicy>(state)) return;
  const Index n = static_cast<Index>(state.range(0));
  SortInput input(n);
  DiscreteVariable<std::uint32_t> keys_out("keys out", n), values_out("values out", n);
  const std::uint32_t* keys_in = input.keys.read(par_device).data();
  const std::uint32_t* values_in = input.values.read(par_device).data();
  std::uint32_t* k_out = keys_out.write(par_device).data();
  std::uint32_t* v_out = values_out.write(par_device).data();
  const CopyPairs reset{input.pristine_keys.read(par_device), input.indices.read(par_device),
                        input.keys.write(par_device), input.values.write(par_device)};
  cudaStream_t stream = static_cast<cudaStream_t>(unisph::cuda::stream_handle());
  std::size_t temp_bytes = 0;
  check(cub::DeviceRadixSort::SortPairs(nullptr, temp_bytes, keys_in, k_out, values_in, v_out, n, 0, 32, stream),
        "sizing");
  void* temp = unisph::cuda::allocate(temp_bytes, "CUB temporary storage");  // allocated once, reused
  for (auto _ : state) {
    particle_for(par_device, n, reset);
    fence(par_device);
    const auto start = std::chrono::steady_clock::now();
    check(cub::DeviceRadixSort::SortPairs(temp, temp_bytes, keys_in, k_out, values_in, v_out, n, 0, 32, stream),
          "SortPairs");
    check(cudaStreamSynchronize(stream), "SortPairs");
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  unisph::cuda::deallocate(temp);
  state.SetItemsProcessed(state.iterations() * int64_t(n));
  state.SetLabel("cub::DeviceRadixSort::SortPairs direct, uint32 pairs, N=" + std::to_string(n));
}
#endif

constexpr int64_t smallest = 100'000, largest = 100'000'000;

#define UNISPH_EXEC_BENCHMARKS(Policy)                                                                  \
  BENCHMARK_TEMPLATE(Triad, Policy)->RangeMultiplier(10)->Range(smallest, largest)->UseRealTime();    \
  BENCHMARK_TEMPLATE(Reduce, Policy)->RangeMultiplier(10)->Range(smallest, largest)->UseRealTime();   \
  BENCHMARK_TEMPLATE(DeterministicReduce, Policy)->RangeMultiplier(10)->Range(smallest, largest)->UseRealTime(); \
  BENCHMARK_TEMPLATE(Scan, Policy)->RangeMultiplier(10)->Range(smallest, largest)->UseRealTime();     \
  BENCHMARK_TEMPLATE(SortPairs, Policy)->RangeMultiplier(10)->Range(smallest, largest)->Arg(1 << 24)->UseManualTime(); \
  BENCHMARK_TEMPLATE(Compute, Policy)->Arg(1'000'000)->UseRealTime();

UNISPH_EXEC_BENCHMARKS(SequencedPolicy)
UNISPH_EXEC_BENCHMARKS(ParallelPolicy)
BENCHMARK(TwoThreadTriad)->Arg(10'000'000)->UseRealTime();
BENCHMARK(ParTriadAgainstTwoThreads)->Arg(10'000'000)->UseManualTime()->MinTime(2.0);
#if UNISPH_HAS_CUDA && defined(__CUDACC__)
UNISPH_EXEC_BENCHMARKS(ParallelDevicePolicy)
BENCHMARK(DeviceMemcpy)->RangeMultiplier(10)->Range(smallest, largest)->UseRealTime();
BENCHMARK(CubSortPairs)->RangeMultiplier(10)->Range(smallest, largest)->Arg(1 << 24)->UseManualTime();
#endif

std::string cpu_model() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  const ExecutionInfo& info = execution_info();
  benchmark::AddCustomContext("unisph_precision", precision());
  benchmark::AddCustomContext("unisph_cpu", cpu_model());
  benchmark::AddCustomContext("unisph_host_threads", std::to_string(host_threads()));
  benchmark::AddCustomContext("unisph_gpu", policy_available(PolicyKind::device) ? info.device_name
                                                                                 : info.device_unavailable_reason);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
