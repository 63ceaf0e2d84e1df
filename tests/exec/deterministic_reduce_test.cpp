// deterministic_reduce: on every policy the bits of the reference association written out below
// (backend/reduction_tree.hpp: blocks of 256 by the halving tree, then the block results the
// same way), for random doubles and floats of mixed magnitude and sign, whose sums depend on the
// association in the last bits; sizes around the block width and over three levels.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/exec/algorithms.hpp"

namespace {
using namespace unisph;

// Mantissa in [1, 2), exponent in [-30, 30], either sign: sums lose bits to cancellation and
// rounding differently for every association.
template <class T>
std::vector<T> mixed_magnitudes(Index n, std::uint64_t seed) {
  std::vector<T> v(n);
  std::uint64_t state = seed;
  const auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return state >> 11;
  };
  for (Index i = 0; i < n; ++i) {
    const double mantissa = 1.0 + double(next() % (1ull << 52)) / double(1ull << 52);
    const int exponent = int(next() % 61) - 30;
    v[i] = T((next() & 1 ? -1.0 : 1.0) * std::ldexp(mantissa, exponent));
  }
  return v;
}

// The reference order, written out independently of the backends.
template <class T, class Op>
T reference_tree(std::vector<T> level, T identity, const Op& op) {
  if (level.empty()) return identity;
  const std::size_t width = 256;
  while (true) {
    std::vector<T> next;
    for (std::size_t begin = 0; begin < level.size(); begin += width) {
      std::vector<T> v(width, identity);
      for (std::size_t t = 0; t < width && begin + t < level.size(); ++t) v[t] = level[begin + t];
      for (std::size_t s = width / 2; s >= 1; s /= 2)
        for (std::size_t t = 0; t < s; ++t) v[t] = op(v[t], v[t + s]);
      next.push_back(v[0]);
    }
    if (next.size() == 1) return next[0];
    level = next;
  }
}

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

template <class T>
struct Item {
  View<const T> values;
  UNISPH_HOST_DEVICE T operator()(Index i) const { return values[i]; }
};

// A (sum, largest) pair per item, as ResidualNorms reduces it, and a vector sum.
struct SumAndMax {
  UNISPH_HOST_DEVICE Vec<double, 2> operator()(const Vec<double, 2>& a, const Vec<double, 2>& b) const {
    return Vec<double, 2>{{a[0] + b[0], a[1] > b[1] ? a[1] : b[1]}};
  }
};
struct PairOfItem {
  View<const double> values;
  UNISPH_HOST_DEVICE Vec<double, 2> operator()(Index i) const { return Vec<double, 2>{{values[i], values[i]}}; }
};
struct TripleOfItem {
  View<const double> values;
  UNISPH_HOST_DEVICE Vec<double, 3> operator()(Index i) const {
    const double x = values[i];
    return Vec<double, 3>{{x, x * x, -x * 3}};
  }
};

const Index sizes[] = {0, 1, 2, 255, 256, 257, 256 * 256, 256 * 256 + 1, 1'000'003};

UNISPH_POLICY_TEST_SUITE(DeterministicReduce);

template <class T, class P>
void check_scalar_sums(P policy) {
  for (const Index n : sizes) {
    const std::vector<T> host = mixed_magnitudes<T>(n, 17 + n);
    DiscreteVariable<T> v("v");
    v.assign(host);
    const T expected = reference_tree(host, T(0), Sum<T>{});
    const T got = deterministic_reduce(policy, n, Sum<T>{}, Item<T>{v.read(policy)});
    const T on_seq = deterministic_reduce(seq, n, Sum<T>{}, Item<T>{v.read(seq)});
    EXPECT_TRUE(same_bits(got, expected)) << "n = " << n << ": " << got << " against the reference's " << expected;
    EXPECT_TRUE(same_bits(got, on_seq)) << "n = " << n;
    // A sum: within rounding of the exact one (long double accumulates far more precisely).
    long double exact = 0, magnitude = 0;
    for (const T x : host) exact += x, magnitude += std::abs(x);
    EXPECT_LE(std::abs((long double)got - exact), magnitude * 64 * std::numeric_limits<T>::epsilon()) << "n = " << n;
  }
}

TYPED_TEST(DeterministicReduce, DoubleSumsHaveTheReferenceBits) { check_scalar_sums<double>(this->policy); }
TYPED_TEST(DeterministicReduce, FloatSumsHaveTheReferenceBits) { check_scalar_sums<float>(this->policy); }

TYPED_TEST(DeterministicReduce, VectorsAndMixedOperations) {
  for (const Index n : sizes) {
    const std::vector<double> host = mixed_magnitudes<double>(n, 5 * n + 1);
    DiscreteVariable<double> v("v");
    v.assign(host);
    std::vector<Vec<double, 2>> pairs(n);
    std::vector<Vec<double, 3>> triples(n);
    for (Index i = 0; i < n; ++i) {
      pairs[i] = Vec<double, 2>{{host[i], host[i]}};
      triples[i] = Vec<double, 3>{{host[i], host[i] * host[i], -host[i] * 3}};
    }
    const Vec<double, 2> identity{{0.0, -INFINITY}};
    const Vec<double, 2> pair =
        deterministic_reduce(this->policy, n, identity, SumAndMax{}, PairOfItem{v.read(this->policy)});
    EXPECT_TRUE(same_bits(pair, reference_tree(pairs, identity, SumAndMax{}))) << "n = " << n;
    const Vec<double, 3> triple =
        deterministic_reduce(this->policy, n, Sum<Vec<double, 3>>{}, TripleOfItem{v.read(this->policy)});
    EXPECT_TRUE(same_bits(triple, reference_tree(triples, Vec<double, 3>{}, Sum<Vec<double, 3>>{}))) << "n = " << n;
  }
}

// The same bits for any number of host threads (par under 1 thread and the machine's).
TYPED_TEST(DeterministicReduce, IndependentOfTheThreadCount) {
  const Index n = 1'000'003;
  const std::vector<double> host = mixed_magnitudes<double>(n, 99);
  DiscreteVariable<double> v("v");
  v.assign(host);
  const double expected = reference_tree(host, 0.0, Sum<double>{});
  set_host_threads(1);
  const double one = deterministic_reduce(this->policy, n, Sum<double>{}, Item<double>{v.read(this->policy)});
  set_host_threads(0);
  const double all = deterministic_reduce(this->policy, n, Sum<double>{}, Item<double>{v.read(this->policy)});
  EXPECT_TRUE(same_bits(one, expected));
  EXPECT_TRUE(same_bits(all, expected));
}

}  // namespace
