// `unisph demo`: runs real kernels (a triad method, a reduction, a scan and a radix sort) on
// every policy this machine offers, checks that each policy computed what seq computed, and
// prints where each ran and how fast.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "commands.hpp"
#include "unisph/unisph.hpp"

namespace unisph::app {

namespace {

// a = b + scale * c, written as a method (kernel shell) with its nested kernel.
class TriadMethod : public UpdateDynamics<TriadMethod> {
 public:
  TriadMethod(DiscreteVariable<Real>& a, DiscreteVariable<Real>& b, DiscreteVariable<Real>& c, Real scale)
      : a_(a), b_(b), c_(c), scale_(scale) {}
  struct Kernel {
    View<Real> a;
    View<const Real> b, c;
    Real scale;
    UNISPH_HOST_DEVICE void update(Index i, Real) const { a[i] = b[i] + scale * c[i]; }
  };
  Kernel make_kernel(KernelContext& context) { return {context.write(a_), context.read(b_), context.read(c_), scale_}; }
  Index size() const { return a_.size(); }

 private:
  DiscreteVariable<Real>& a_;
  DiscreteVariable<Real>& b_;
  DiscreteVariable<Real>& c_;
  Real scale_;
};

struct ValueOf {
  View<const Real> v;
  UNISPH_HOST_DEVICE Real operator()(Index i) const { return v[i]; }
};

struct Results {
  std::vector<Real> triad;
  Real sum = 0;
  std::vector<std::uint32_t> scan, sorted_keys, sorted_values;
};

struct Timing {
  std::string policy, operation;
  double milliseconds;
  std::string throughput;
};

template <class F>
double best_of(int repeat, F&& run) {
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const auto start = std::chrono::steady_clock::now();
    run();
    best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

std::string rate(double amount, double milliseconds, const char* unit) {
  char text[64];
  const double per_second = amount / (milliseconds * 1e-3);
  if (per_second >= 1e9)
    std::snprintf(text, sizeof text, "%.2f G%s/s", per_second * 1e-9, unit);
  else
    std::snprintf(text, sizeof text, "%.2f M%s/s", per_second * 1e-6, unit);
  return text;
}

template <class P>
Results run_policy(P policy, Index n, int repeat, std::vector<Timing>& timings) {
  const std::string name(P::name);
  // Integer-valued inputs: the triad, the sum and the scan are exact, so every policy must agree exactly.
  DiscreteVariable<Real> a("a", n), b("b", n), c("c", n);
  {
    View<Real> hb = b.write(MemorySpace::host), hc = c.write(MemorySpace::host);
    for (Index i = 0; i < n; ++i) {
      hb[i] = Real(i % 1000);
      hc[i] = Real(i % 7);
    }
  }
  TriadMethod triad(a, b, c, Real(3));
  triad.exec(policy);  // warm-up: builds the kernel, copies b and c where the policy needs them
  fence(policy);
  double ms = best_of(repeat, [&] {
    triad.exec(policy);
    fence(policy);
  });
  timings.push_back({name, "triad a = b + 3c (particle_for)", ms, rate(3.0 * n * sizeof(Real), ms, "B")});

  Results results;
  ms = best_of(repeat, [&] { results.sum = particle_reduce(policy, n, Sum<Real>{}, ValueOf{a.read(policy)}); });
  timings.push_back({name, "sum of a (particle_reduce)", ms, rate(double(n) * sizeof(Real), ms, "B")});

  DiscreteVariable<std::uint32_t> counts("counts", n), offsets("offsets", n + 1);
  {
    View<std::uint32_t> h = counts.write(MemorySpace::host);
    for (Index i = 0; i < n; ++i) h[i] = static_cast<std::uint32_t>(i % 5);
  }
  exclusive_scan(policy, counts.read(policy), offsets.write(policy));
  fence(policy);
  ms = best_of(repeat, [&] {
    exclusive_scan(policy, counts.read(policy), offsets.write(policy));
    fence(policy);
  });
  timings.push_back({name, "exclusive_scan of uint32", ms, rate(double(n), ms, "items")});

  // Sorting changes its input, so each repetition starts from fresh random keys (not timed).
  std::vector<std::uint32_t> random_keys(n);
  std::mt19937 rng(42);
  for (auto& k : random_keys) k = static_cast<std::uint32_t>(rng());
  DiscreteVariable<std::uint32_t> keys("keys", n), values("values", n);
  double sort_ms = 1e300;
  for (int r = 0; r < std::max(repeat, 1); ++r) {
    keys.assign(random_keys);
    {
      View<std::uint32_t> h = values.write(MemorySpace::host);
      for (Index i = 0; i < n; ++i) h[i] = static_cast<std::uint32_t>(i);
    }
    (void)keys.read_write(policy);
    (void)values.read_write(policy);
    fence(policy);
    sort_ms = std::min(sort_ms, best_of(1, [&] {
                         sort_pairs(policy, keys, values);
                         fence(policy);
                       }));
  }
  timings.push_back({name, "sort_pairs of uint32 keys + values", sort_ms, rate(double(n), sort_ms, "keys")});

  results.triad = a.to_vector();
  results.scan = offsets.to_vector();
  results.sorted_keys = keys.to_vector();
  results.sorted_values = values.to_vector();
  return results;
}

bool same(const Results& x, const Results& y) {
  return x.triad == y.triad && x.sum == y.sum && x.scan == y.scan && x.sorted_keys == y.sorted_keys &&
         x.sorted_values == y.sorted_values;
}

}  // namespace

void add_demo_command(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "demo", "run real kernels on every policy this machine offers, check that they agree, and time them");
  struct Options {
    Index items = 10'000'000;
    int repeat = 5;
    std::vector<std::string> policies;
    int threads = 0;
  };
  static Options options;
  command->add_option("-n,--items", options.items, "items per kernel")->check(CLI::Range(Index(1), Index(1) << 31))
      ->capture_default_str();
  command->add_option("--repeat", options.repeat, "timed repetitions (the best is shown)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  command->add_option("--policy", options.policies, "policies to run (default: every one available here)")
      ->check(CLI::IsMember({"seq", "par", "device"}));
  command->add_option("--threads", options.threads, "CPU threads for the par policy (0: all)")
      ->check(CLI::NonNegativeNumber);
  command->callback([] {
    set_host_threads(options.threads);
    std::vector<PolicyKind> kinds;
    if (options.policies.empty()) {
      kinds = execution_info().available;
    } else {
      for (const std::string& p : options.policies) kinds.push_back(parse_policy(p));
    }
    const ExecutionInfo& info = execution_info();
    std::printf("unisph demo: %zu items per kernel, Real = %s, best of %d runs\n", options.items,
                sizeof(Real) == 8 ? "double" : "float", options.repeat);
    std::printf("  CPU: %d threads for par\n", host_threads());
    if (policy_available(PolicyKind::device))
      std::printf("  GPU: %s (%d multiprocessors)\n", info.device_name.c_str(), info.device_multiprocessors);
    else
      std::printf("  GPU: not used: %s\n", info.device_unavailable_reason.c_str());

    std::vector<Timing> timings;
    std::vector<std::pair<PolicyKind, Results>> results;
    for (PolicyKind kind : kinds) {
      std::printf("  running on %s ...\n", std::string(to_string(kind)).c_str());
      std::fflush(stdout);
      results.emplace_back(kind, visit_policy(kind, [&](auto policy) {
                             return run_policy(policy, options.items, options.repeat, timings);
                           }));
    }
    std::printf("\n%-7s %-38s %12s %16s\n", "policy", "kernel", "time [ms]", "throughput");
    for (const Timing& t : timings)
      std::printf("%-7s %-38s %12.3f %16s\n", t.policy.c_str(), t.operation.c_str(), t.milliseconds,
                  t.throughput.c_str());
    std::printf("\n");
    bool agree = true;
    for (const auto& [kind, r] : results) {
      const bool ok = same(r, results.front().second);
      agree = agree && ok;
      std::printf("%-7s results %s %s (sum of the triad = %.17g)\n", std::string(to_string(kind)).c_str(),
                  ok ? "identical to" : "DIFFER from", std::string(to_string(results.front().first)).c_str(),
                  double(r.sum));
    }
    if (!agree) throw Error("the policies computed different results");
  });
}

}  // namespace unisph::app
