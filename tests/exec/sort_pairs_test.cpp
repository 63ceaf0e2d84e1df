// sort_pairs: sorted, stable, a permutation of the input; random, all-equal, presorted and
// reversed keys; 32- and 64-bit keys; sizes from 0 to 10^7; partial bit ranges.
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"

namespace {
using namespace unisph;

enum class Order { random, all_equal, presorted, reversed, few_distinct };

template <class K>
std::vector<K> make_keys(Index n, Order order) {
  std::vector<K> keys(n);
  std::mt19937_64 rng(1234 + n);
  switch (order) {
    case Order::random:
      for (auto& k : keys) k = static_cast<K>(rng());
      break;
    case Order::all_equal:
      std::fill(keys.begin(), keys.end(), static_cast<K>(0xA5A5A5A5A5A5A5A5ull));
      break;
    case Order::presorted:
      for (Index i = 0; i < n; ++i) keys[i] = static_cast<K>(i * 3);
      break;
    case Order::reversed:
      for (Index i = 0; i < n; ++i) keys[i] = static_cast<K>((n - i) * 3);
      break;
    case Order::few_distinct:
      for (auto& k : keys) k = static_cast<K>(rng() % 7) << (8 * sizeof(K) - 8);
      break;
  }
  return keys;
}

// Values are the original positions, so stability and the permutation can be checked exactly.
template <class K, class V, class P>
void check_sort(P policy, Index n, Order order, int begin_bit = 0, int end_bit = int(8 * sizeof(K))) {
  const std::vector<K> original = make_keys<K>(n, order);
  DiscreteVariable<K> keys("keys");
  DiscreteVariable<V> values("values", n);
  keys.assign(original);
  {
    View<V> host = values.write(MemorySpace::host);
    for (Index i = 0; i < n; ++i) host[i] = static_cast<V>(i);
  }
  sort_pairs(policy, keys, values, begin_bit, end_bit);
  const std::vector<K> k = keys.to_vector();
  const std::vector<V> v = values.to_vector();
  const K mask = end_bit - begin_bit == int(8 * sizeof(K))
                     ? ~K(0)
                     : static_cast<K>(((K(1) << (end_bit - begin_bit)) - 1) << begin_bit);
  Index errors = 0;
  for (Index i = 0; i < n; ++i) {
    const Index from = static_cast<Index>(v[i]);
    if (from >= n || original[from] != k[i]) ++errors;  // a permutation carrying its key
    if (i > 0) {
      const K a = k[i - 1] & mask, b = k[i] & mask;
      if (a > b) ++errors;                                  // sorted
      if (a == b && v[i - 1] >= v[i]) ++errors;             // stable
    }
  }
  EXPECT_EQ(errors, 0u) << "n = " << n << ", order " << static_cast<int>(order) << ", bits [" << begin_bit << ", "
                        << end_bit << ")";
}

const Index sizes[] = {0, 1, 2, 1023, 1025, 65535, 65537};
const Order orders[] = {Order::random, Order::all_equal, Order::presorted, Order::reversed, Order::few_distinct};

UNISPH_POLICY_TEST_SUITE(SortPairs);

TYPED_TEST(SortPairs, Keys32Values32) {
  for (Index n : sizes)
    for (Order o : orders) check_sort<std::uint32_t, std::uint32_t>(this->policy, n, o);
}
TYPED_TEST(SortPairs, Keys64Values32) {
  for (Index n : sizes)
    for (Order o : orders) check_sort<std::uint64_t, std::uint32_t>(this->policy, n, o);
}
TYPED_TEST(SortPairs, Keys32Values64AndKeys64Values64) {
  for (Order o : orders) {
    check_sort<std::uint32_t, std::uint64_t>(this->policy, 65537, o);
    check_sort<std::uint64_t, std::uint64_t>(this->policy, 65537, o);
  }
}
TYPED_TEST(SortPairs, TenMillionRandomKeys) {
  check_sort<std::uint32_t, std::uint32_t>(this->policy, 10'000'000, Order::random);
  check_sort<std::uint64_t, std::uint32_t>(this->policy, 10'000'000, Order::random);
}
TYPED_TEST(SortPairs, PartialBitRanges) {
  check_sort<std::uint32_t, std::uint32_t>(this->policy, 100'003, Order::random, 0, 12);
  check_sort<std::uint64_t, std::uint32_t>(this->policy, 100'003, Order::random, 20, 63);
  check_sort<std::uint64_t, std::uint32_t>(this->policy, 100'003, Order::random, 0, 0);
}
TYPED_TEST(SortPairs, FloatValuesTravelAsBits) {
  DiscreteVariable<std::uint32_t> keys("keys", {5, 3, 9, 3});
  DiscreteVariable<float> values("values", {0.5f, -1.25f, 3e10f, 7.0f});
  sort_pairs(this->policy, keys, values);
  EXPECT_EQ(keys.to_vector(), (std::vector<std::uint32_t>{3, 3, 5, 9}));
  EXPECT_EQ(values.to_vector(), (std::vector<float>{-1.25f, 7.0f, 0.5f, 3e10f}));
}
TYPED_TEST(SortPairs, RejectsMismatchedSizesAndBitRanges) {
  DiscreteVariable<std::uint32_t> keys("keys", 10);
  DiscreteVariable<std::uint32_t> values("values", 9);
  EXPECT_THROW(sort_pairs(this->policy, keys, values), Error);
  values.resize(10);
  EXPECT_THROW(sort_pairs(this->policy, keys, values, 0, 33), Error);
}

}  // namespace
