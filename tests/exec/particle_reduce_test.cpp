// particle_reduce against exact results: integer-valued data, so every sum is exact.
#include <cstdint>
#include <limits>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/exec/algorithms.hpp"

namespace {
using namespace unisph;

// Value of item i: integers in [-500, 499], a pattern with known sum, min and max.
UNISPH_HOST_DEVICE inline std::int64_t pattern(Index i) { return static_cast<std::int64_t>((i * 7919) % 1000) - 500; }

template <class T>
struct PatternValue {
  View<const T> values;
  UNISPH_HOST_DEVICE T operator()(Index i) const { return values[i]; }
};

template <class T>
void fill_pattern(DiscreteVariable<T>& v) {
  View<T> host = v.write(MemorySpace::host);
  for (Index i = 0; i < host.size(); ++i) host[i] = static_cast<T>(pattern(i));
}

struct ExactResult {
  std::int64_t sum = 0, min = std::numeric_limits<std::int64_t>::max(), max = std::numeric_limits<std::int64_t>::min();
};
ExactResult exact(Index n) {
  ExactResult r;
  for (Index i = 0; i < n; ++i) {
    r.sum += pattern(i);
    r.min = std::min(r.min, pattern(i));
    r.max = std::max(r.max, pattern(i));
  }
  return r;
}

UNISPH_POLICY_TEST_SUITE(ParticleReduce);

TYPED_TEST(ParticleReduce, SumMinMaxOfDoublesAreExact) {
  for (Index n : {Index(0), Index(1), Index(2), Index(1023), Index(1025), Index(65537), Index(10'000'000)}) {
    DiscreteVariable<double> v("v", n);
    fill_pattern(v);
    const ExactResult ref = exact(n);
    const PatternValue<double> f{v.read(this->policy)};
    EXPECT_EQ(particle_reduce(this->policy, n, Sum<double>{}, f), static_cast<double>(ref.sum)) << "n = " << n;
    if (n == 0) {
      EXPECT_EQ(particle_reduce(this->policy, n, Min<double>{}, f), std::numeric_limits<double>::infinity());
      EXPECT_EQ(particle_reduce(this->policy, n, Max<double>{}, f), -std::numeric_limits<double>::infinity());
    } else {
      EXPECT_EQ(particle_reduce(this->policy, n, Min<double>{}, f), static_cast<double>(ref.min)) << "n = " << n;
      EXPECT_EQ(particle_reduce(this->policy, n, Max<double>{}, f), static_cast<double>(ref.max)) << "n = " << n;
    }
  }
}

TYPED_TEST(ParticleReduce, FloatAndIntegerSums) {
  const Index n = (Index(1) << 20) + 1;  // partial sums stay below 2^24: exact in float
  DiscreteVariable<float> f("f", n);
  DiscreteVariable<std::int64_t> k("k", n);
  fill_pattern(f);
  fill_pattern(k);
  const ExactResult ref = exact(n);
  EXPECT_EQ(particle_reduce(this->policy, n, Sum<float>{}, PatternValue<float>{f.read(this->policy)}),
            static_cast<float>(ref.sum));
  EXPECT_EQ(particle_reduce(this->policy, n, Sum<std::int64_t>{}, PatternValue<std::int64_t>{k.read(this->policy)}),
            ref.sum);
  EXPECT_EQ(particle_reduce(this->policy, n, Min<std::int64_t>{}, PatternValue<std::int64_t>{k.read(this->policy)}),
            ref.min);
}

// A small vector per item: sums and componentwise min/max.
struct VectorOfItem {
  UNISPH_HOST_DEVICE Vec<double, 3> operator()(Index i) const {
    return {{static_cast<double>(pattern(i)), static_cast<double>(i % 17), -static_cast<double>(i % 5)}};
  }
};

TYPED_TEST(ParticleReduce, SmallVectors) {
  const Index n = 100'003;
  Vec<double, 3> sum{}, lo = Vec<double, 3>::constant(1e300), hi = Vec<double, 3>::constant(-1e300);
  for (Index i = 0; i < n; ++i) {
    const Vec<double, 3> x = VectorOfItem{}(i);
    sum += x;
    lo = min(lo, x);
    hi = max(hi, x);
  }
  EXPECT_EQ(particle_reduce(this->policy, n, Sum<Vec<double, 3>>{}, VectorOfItem{}), sum);
  EXPECT_EQ(particle_reduce(this->policy, n, Min<Vec<double, 3>>{}, VectorOfItem{}), lo);
  EXPECT_EQ(particle_reduce(this->policy, n, Max<Vec<double, 3>>{}, VectorOfItem{}), hi);
}

// A user operation with its identity: bitwise or of 32-bit masks, and a (count, sum) pair.
struct BitOr {
  UNISPH_HOST_DEVICE std::uint32_t operator()(std::uint32_t a, std::uint32_t b) const { return a | b; }
};
struct BitOfItem {
  UNISPH_HOST_DEVICE std::uint32_t operator()(Index i) const { return std::uint32_t(1) << ((i * 5) % 29); }
};
struct CountAndSum {
  std::int64_t count;
  double sum;
};
struct CombineCountAndSum {
  UNISPH_HOST_DEVICE CountAndSum operator()(const CountAndSum& a, const CountAndSum& b) const {
    return {a.count + b.count, a.sum + b.sum};
  }
};
struct PositiveItems {
  UNISPH_HOST_DEVICE CountAndSum operator()(Index i) const {
    const std::int64_t v = pattern(i);
    return v > 0 ? CountAndSum{1, static_cast<double>(v)} : CountAndSum{0, 0.0};
  }
};

TYPED_TEST(ParticleReduce, UserOperations) {
  const Index n = 65'537;
  std::uint32_t bits = 0;
  CountAndSum ref{0, 0.0};
  for (Index i = 0; i < n; ++i) {
    bits |= BitOfItem{}(i);
    const CountAndSum c = PositiveItems{}(i);
    ref.count += c.count;
    ref.sum += c.sum;
  }
  EXPECT_EQ(particle_reduce(this->policy, n, std::uint32_t(0), BitOr{}, BitOfItem{}), bits);
  const CountAndSum got = particle_reduce(this->policy, n, CountAndSum{0, 0.0}, CombineCountAndSum{}, PositiveItems{});
  EXPECT_EQ(got.count, ref.count);
  EXPECT_EQ(got.sum, ref.sum);
}

// Back-to-back reductions of different types and sizes, interleaved with kernels that change
// the data: each result is the one of its own launch (the result buffer and the partials are
// reused between launches).
struct AddIndexParity {
  View<double> v;
  UNISPH_HOST_DEVICE void operator()(Index i) const { v[i] += static_cast<double>(i % 2); }
};

TYPED_TEST(ParticleReduce, BackToBackReductionsOfDifferentTypes) {
  const Index sizes[] = {1, 1000, 1'000'003, 77};
  DiscreteVariable<double> v("v", 1'000'003);
  fill_pattern(v);
  std::vector<double> host = v.to_vector();
  for (int round = 0; round < 20; ++round) {
    const Index n = sizes[round % 4];
    double sum = 0;
    for (Index i = 0; i < n; ++i) sum += host[i];
    EXPECT_EQ(particle_reduce(this->policy, n, Sum<double>{}, PatternValue<double>{v.read(this->policy)}), sum)
        << "round " << round;
    const Vec<double, 3> vec_sum = particle_reduce(this->policy, n, Sum<Vec<double, 3>>{}, VectorOfItem{});
    Vec<double, 3> ref{};
    for (Index i = 0; i < n; ++i) ref += VectorOfItem{}(i);
    EXPECT_EQ(vec_sum, ref) << "round " << round;
    particle_for(this->policy, v.size(), AddIndexParity{v.read_write(this->policy)});
    for (Index i = 0; i < host.size(); ++i) host[i] += static_cast<double>(i % 2);
  }
}

// Heavy items: each item sums its own run of a long array (like a thread walking a whole
// cell), 8192 items over 8 million values.
struct SumOfRun {
  View<const std::uint64_t> run_begin;
  View<const double> values;
  UNISPH_HOST_DEVICE double operator()(Index i) const {
    double sum = 0;
    for (std::uint64_t k = run_begin[i]; k < run_begin[i + 1]; ++k) sum += values[k];
    return sum;
  }
};

TYPED_TEST(ParticleReduce, HeavyItems) {
  const Index items = 8192;
  std::vector<std::uint64_t> begin(items + 1, 0);
  std::uint64_t state = 12345;
  for (Index i = 0; i < items; ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    begin[i + 1] = begin[i] + 200 + (state >> 33) % 1600;
  }
  DiscreteVariable<std::uint64_t> run_begin("run_begin");
  run_begin.assign(begin);
  DiscreteVariable<double> values("values", begin[items]);
  double ref = 0;
  {
    View<double> h = values.write(MemorySpace::host);
    for (Index k = 0; k < h.size(); ++k) ref += (h[k] = static_cast<double>(k % 1000));
  }
  const SumOfRun f{run_begin.read(this->policy), values.read(this->policy)};
  EXPECT_EQ(particle_reduce(this->policy, items, Sum<double>{}, f), ref);
  EXPECT_EQ(particle_reduce(this->policy, items, Sum<double>{}, f), ref);
}

}  // namespace
