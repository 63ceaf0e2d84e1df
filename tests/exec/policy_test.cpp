// Policy names, the run-time query, and the errors for an unavailable device.
#include <string>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"

namespace {
using namespace unisph;

TEST(HostPolicy, OneMappingOfNames) {
  EXPECT_EQ(SequencedPolicy::name, "seq");
  EXPECT_EQ(ParallelPolicy::name, "par");
  EXPECT_EQ(ParallelDevicePolicy::name, "device");
  EXPECT_EQ(ParallelDevicePolicy::test_label, "gpu");
  EXPECT_EQ(parse_policy("seq"), PolicyKind::seq);
  EXPECT_EQ(parse_policy("par"), PolicyKind::par);
  EXPECT_EQ(parse_policy("device"), PolicyKind::device);
  EXPECT_EQ(to_string(PolicyKind::device), "device");
  try {
    parse_policy("gpu");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "unknown execution policy 'gpu': expected seq, par or device");
  }
}

TEST(HostPolicy, QueryTellsWhatRunsHere) {
  const ExecutionInfo& info = execution_info();
  ASSERT_GE(info.available.size(), 2u);
  EXPECT_EQ(info.available[0], PolicyKind::seq);
  EXPECT_EQ(info.available[1], PolicyKind::par);
  EXPECT_EQ(info.cuda_built, bool(UNISPH_HAS_CUDA));
  EXPECT_EQ(policy_available(PolicyKind::device), info.cuda_built && info.device_present);
  EXPECT_GE(host_threads(), 1);
  if (!policy_available(PolicyKind::device)) {
    EXPECT_FALSE(info.device_unavailable_reason.empty());
    EXPECT_EQ(info.available.size(), 2u);
    try {
      require_policy(PolicyKind::device);
      FAIL() << "expected PolicyUnavailable";
    } catch (const PolicyUnavailable& e) {
      EXPECT_NE(std::string(e.what()).find(info.device_unavailable_reason), std::string::npos);
    }
  }
}

#if !UNISPH_HAS_CUDA
struct Nothing {
  void operator()(Index) const {}
};
#endif

TEST(HostPolicy, VisitPolicyRunsTheChosenOneOrThrows) {
  EXPECT_EQ(visit_policy(PolicyKind::seq, [](auto p) { return std::string(decltype(p)::name); }), "seq");
  EXPECT_EQ(visit_policy(PolicyKind::par, [](auto p) { return std::string(decltype(p)::name); }), "par");
  if (policy_available(PolicyKind::device)) {
    EXPECT_EQ(visit_policy(PolicyKind::device, [](auto p) { return std::string(decltype(p)::name); }), "device");
  } else {
    EXPECT_THROW(visit_policy(PolicyKind::device, [](auto p) { return std::string(decltype(p)::name); }),
                 PolicyUnavailable);
#if !UNISPH_HAS_CUDA
    // Without the backend the device policy still compiles, and fails at run time.
    EXPECT_THROW(particle_for(par_device, 10, Nothing{}), PolicyUnavailable);
#endif
  }
}

TEST(HostPolicy, ThreadLimit) {
  set_host_threads(1);
  EXPECT_EQ(host_threads(), 1);
  set_host_threads(0);
  EXPECT_GE(host_threads(), 1);
}

}  // namespace
