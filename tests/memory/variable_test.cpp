// Host/device coherence of DiscreteVariable and SingularVariable: the contents follow every
// access, nothing is copied that need not be, resizing keeps contents on both sides.
#include <cstdint>
#include <string>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/memory/discrete_variable.hpp"
#include "unisph/memory/singular_variable.hpp"

namespace {
using namespace unisph;

struct DoublePlusOne {
  View<double> v;
  UNISPH_HOST_DEVICE void operator()(Index i) const { v[i] = 2 * v[i] + 1; }
};
struct CopyInto {
  View<const double> from;
  View<double> to;
  UNISPH_HOST_DEVICE void operator()(Index i) const { to[i] = from[i]; }
};
struct AddToSingular {
  View<double> total;
  View<const double> v;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    if (i == 0) total[0] += v[0];
  }
};

UNISPH_POLICY_TEST_SUITE(Variable);

// host write -> device read -> device write -> host read -> resize -> device read
TYPED_TEST(Variable, CoherenceSequence) {
  const auto policy = this->policy;
  const bool device = decltype(policy)::space == MemorySpace::device;
  const Index n = 100'000;
  DiscreteVariable<double> v("v", n);
  DiscreteVariable<double> copy("copy", n);
  {
    View<double> host = v.write(MemorySpace::host);
    for (Index i = 0; i < n; ++i) host[i] = static_cast<double>(i);
  }
  // Device read sees the host's values.
  particle_for(policy, n, CopyInto{v.read(policy), copy.write(policy)});
  EXPECT_EQ(copy.to_vector(), v.to_vector());
  EXPECT_EQ(v.copies_to_device(), device ? 1u : 0u);
  // A second read copies nothing.
  particle_for(policy, n, CopyInto{v.read(policy), copy.write(policy)});
  EXPECT_EQ(v.copies_to_device(), device ? 1u : 0u);
  // Device write; host read sees it (one copy back).
  particle_for(policy, n, DoublePlusOne{v.read_write(policy)});
  EXPECT_EQ(v.is_current(MemorySpace::host), !device);
  {
    View<const double> host = v.read(MemorySpace::host);
    for (Index i : {Index(0), Index(1), n / 2, n - 1}) EXPECT_EQ(host[i], 2.0 * i + 1) << i;
  }
  EXPECT_EQ(v.copies_to_host(), device ? 1u : 0u);
  (void)v.read(MemorySpace::host);
  EXPECT_EQ(v.copies_to_host(), device ? 1u : 0u);
  // Device write again, then resize while the device holds the only current copy.
  particle_for(policy, n, DoublePlusOne{v.read_write(policy)});
  v.resize(n + 50);
  copy.resize(n + 50);
  particle_for(policy, n + 50, CopyInto{v.read(policy), copy.write(policy)});
  const std::vector<double> after = copy.to_vector();
  for (Index i : {Index(0), Index(7), n - 1}) EXPECT_EQ(after[i], 2.0 * (2.0 * i + 1) + 1) << i;
  for (Index i = n; i < n + 50; ++i) EXPECT_EQ(after[i], 0.0) << "new elements are zero, " << i;
  // Shrinking keeps the prefix.
  v.resize(10);
  EXPECT_EQ(v.to_vector()[9], 2.0 * (2.0 * 9 + 1) + 1);
}

TYPED_TEST(Variable, WriteAccessCopiesNothing) {
  const auto policy = this->policy;
  DiscreteVariable<double> v("v", 1000);
  v.write(MemorySpace::host)[0] = 42;
  (void)v.write(policy);      // all elements will be written: no copy needed
  (void)v.write(MemorySpace::host);
  EXPECT_EQ(v.copies_to_device(), 0u);
  EXPECT_EQ(v.copies_to_host(), 0u);
}

TYPED_TEST(Variable, NewVariablesAreZeroEverywhere) {
  const auto policy = this->policy;
  DiscreteVariable<double> v("v", 1000), out("out", 1000);
  particle_for(policy, 1000, CopyInto{v.read(policy), out.write(policy)});
  EXPECT_EQ(out.to_vector(), std::vector<double>(1000, 0.0));
  EXPECT_EQ(v.copies_to_device(), 0u) << "zeros are set on the device, not copied there";
  v.resize(2000);
  EXPECT_EQ(v.to_vector(), std::vector<double>(2000, 0.0));
}

TYPED_TEST(Variable, SingularVariableFollowsTheDevice) {
  const auto policy = this->policy;
  SingularVariable<double> total("total", 1.5);
  DiscreteVariable<double> v("v", {2.0, 3.0});
  particle_for(policy, 2, AddToSingular{total.read_write(policy), v.read(policy)});
  EXPECT_EQ(total.get(), 3.5);
  total.set(10.0);
  particle_for(policy, 2, AddToSingular{total.read_write(policy), v.read(policy)});
  EXPECT_EQ(total.get(), 12.0);
}

TYPED_TEST(Variable, EmptyVariables) {
  const auto policy = this->policy;
  DiscreteVariable<double> v("empty");
  particle_for(policy, 0, DoublePlusOne{v.read_write(policy)});
  EXPECT_TRUE(v.to_vector().empty());
  v.resize(3);
  EXPECT_EQ(v.to_vector(), std::vector<double>(3, 0.0));
}

// A device allocation that cannot succeed is an exception naming the variable and the size.
TYPED_TEST(Variable, DeviceOutOfMemoryNamesTheVariable) {
  if constexpr (decltype(this->policy)::space == MemorySpace::device) {
    DiscreteVariable<double> huge("HugeField", Index(1) << 47);  // 1 PiB: more than any GPU has
    try {
      (void)huge.write(this->policy);
      FAIL() << "expected a DeviceError";
    } catch (const DeviceError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("HugeField"), std::string::npos) << message;
      EXPECT_NE(message.find(std::to_string((Index(1) << 47) * 8)), std::string::npos) << message;
      EXPECT_NE(message.find("cudaMalloc"), std::string::npos) << message;
    }
    // The process goes on working after the failure.
    DiscreteVariable<double> small("small", {1.0, 2.0});
    particle_for(this->policy, 2, DoublePlusOne{small.read_write(this->policy)});
    EXPECT_EQ(small.to_vector(), (std::vector<double>{3.0, 5.0}));
  }
}

// Where the device cannot run, asking for it is a clear error, never a silent fallback.
TEST(HostVariable, DeviceAccessWithoutDeviceIsAnError) {
  if (policy_available(PolicyKind::device)) GTEST_SKIP() << "a GPU is present";
  DiscreteVariable<double> v("v", 10);
  try {
    (void)v.read(MemorySpace::device);
    FAIL() << "expected PolicyUnavailable";
  } catch (const PolicyUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("device"), std::string::npos) << e.what();
  }
}

}  // namespace
