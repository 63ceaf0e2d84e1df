// exclusive_scan against a sequential scan, in and out of place, with and without the total.
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"

namespace {
using namespace unisph;

const Index sizes[] = {0, 1, 2, 1023, 1025, 65535, 65537, 10'000'000};

template <class T>
std::vector<T> random_input(Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> dist(0, 9);  // small integers: every prefix sum is exact
  std::vector<T> v(n);
  for (auto& x : v) x = static_cast<T>(dist(rng));
  return v;
}

template <class T>
std::vector<T> reference(const std::vector<T>& in) {
  std::vector<T> out(in.size() + 1);
  T running{};
  for (Index i = 0; i < in.size(); ++i) {
    out[i] = running;
    running += in[i];
  }
  out[in.size()] = running;
  return out;
}

template <class T, class P>
void check_scan(P policy, Index n) {
  const std::vector<T> in = random_input<T>(n, 17 + static_cast<unsigned>(n));
  const std::vector<T> ref = reference(in);
  // Out of place, n outputs.
  DiscreteVariable<T> input("input"), output("output", n);
  input.assign(in);
  exclusive_scan(policy, input, output);
  std::vector<T> got = output.to_vector();
  EXPECT_TRUE(std::equal(got.begin(), got.end(), ref.begin())) << "out of place, n = " << n;
  // Out of place, n + 1 outputs: the total lands in out[n].
  DiscreteVariable<T> with_total("with_total", n + 1);
  exclusive_scan(policy, input.read(policy), with_total.write(policy));
  EXPECT_EQ(with_total.to_vector(), ref) << "with total, n = " << n;
  // In place.
  exclusive_scan(policy, input, input);
  got = input.to_vector();
  EXPECT_TRUE(std::equal(got.begin(), got.end(), ref.begin())) << "in place, n = " << n;
}

UNISPH_POLICY_TEST_SUITE(ExclusiveScan);

TYPED_TEST(ExclusiveScan, Unsigned32) {
  for (Index n : sizes) check_scan<std::uint32_t>(this->policy, n);
}
TYPED_TEST(ExclusiveScan, Signed64) {
  for (Index n : sizes) check_scan<std::int64_t>(this->policy, n);
}
TYPED_TEST(ExclusiveScan, Double) {
  for (Index n : {Index(1), Index(65537), Index(1'000'003)}) check_scan<double>(this->policy, n);
}
TYPED_TEST(ExclusiveScan, InPlaceWithTotal) {
  // A CSR offset array: counts in [0, n), the total written to [n].
  const Index n = 100'001;
  const std::vector<int> counts = random_input<int>(n, 5);
  const std::vector<int> ref = reference(counts);
  DiscreteVariable<int> offsets("offsets", n + 1);
  {
    View<int> host = offsets.write(MemorySpace::host);
    for (Index i = 0; i < n; ++i) host[i] = counts[i];
  }
  View<int> all = offsets.read_write(this->policy);
  exclusive_scan(this->policy, View<const int>(all.subview(0, n)), all);
  EXPECT_EQ(offsets.to_vector(), ref);
}
TYPED_TEST(ExclusiveScan, RejectsAnOutputOfTheWrongSize) {
  DiscreteVariable<int> in("in", 10), out("out", 12);
  EXPECT_THROW(exclusive_scan(this->policy, in, out), Error);
}

}  // namespace
