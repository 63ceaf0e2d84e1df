// particle_for: every item visited exactly once, on every policy, at awkward sizes.
#include <cstdint>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/atomic.hpp"

namespace {
using namespace unisph;

struct WriteAffine {
  View<std::int64_t> out;
  UNISPH_HOST_DEVICE void operator()(Index i) const { out[i] = 3 * static_cast<std::int64_t>(i) + 1; }
};

struct CountVisits {
  View<unsigned> visits;
  UNISPH_HOST_DEVICE void operator()(Index i) const { atomic_add(&visits[i], 1u); }
};

UNISPH_POLICY_TEST_SUITE(ParticleFor);

TYPED_TEST(ParticleFor, WritesEveryItemOnce) {
  for (Index n : {Index(0), Index(1), Index(2), Index(1023), Index(1025), Index(65535), Index(65537), Index(10'000'000)}) {
    DiscreteVariable<std::int64_t> out("out", n);
    {
      View<std::int64_t> host = out.write(MemorySpace::host);
      for (Index i = 0; i < n; ++i) host[i] = -7;  // poison: every element must be written
    }
    particle_for(this->policy, n, WriteAffine{out.write(this->policy)});
    DiscreteVariable<unsigned> visits("visits", n);
    particle_for(this->policy, n, CountVisits{visits.read_write(this->policy)});
    View<const std::int64_t> result = out.read(MemorySpace::host);
    View<const unsigned> count = visits.read(MemorySpace::host);
    Index wrong = 0;
    for (Index i = 0; i < n; ++i) wrong += (result[i] != 3 * static_cast<std::int64_t>(i) + 1) + (count[i] != 1);
    EXPECT_EQ(wrong, 0u) << "n = " << n;
  }
}

}  // namespace
