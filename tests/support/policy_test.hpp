#pragma once
// Every test is written once as a typed test over the policies this build has; the names
// the test instances get (seq, par, gpu) are the ctest labels (tests/CMakeLists.txt filters
// on them). Device tests skip with a message where no GPU is present.

#include <gtest/gtest.h>

#include <string>
#include <type_traits>

#include "unisph/exec/policy.hpp"

namespace unisph::testing {

// The gpu instances exist where the source is compiled by nvcc against a CUDA-built library;
// a test compiled as host C++ (UNISPH_GPU_TESTS=OFF, tests/CMakeLists.txt) has seq and par.
#if UNISPH_HAS_CUDA && defined(__CUDACC__)
using Policies = ::testing::Types<SequencedPolicy, ParallelPolicy, ParallelDevicePolicy>;
#else
using Policies = ::testing::Types<SequencedPolicy, ParallelPolicy>;
#endif

struct PolicyNames {
  template <class P>
  static std::string GetName(int) {
    return std::string(P::test_label);
  }
};

template <class P>
class PolicyTest : public ::testing::Test {
 protected:
  static constexpr P policy{};
  void SetUp() override {
    if constexpr (P::space == MemorySpace::device) {
      if (!policy_available(PolicyKind::device))
        GTEST_SKIP() << "GPU test skipped: " << execution_info().device_unavailable_reason;
    }
  }
};

// The run-time kind of a policy type (for code that takes a PolicyKind, such as the solver).
template <class P>
PolicyKind kind_of() {
  if constexpr (P::space == MemorySpace::device) return PolicyKind::device;
  else if constexpr (std::is_same_v<P, SequencedPolicy>) return PolicyKind::seq;
  else return PolicyKind::par;
}

}  // namespace unisph::testing

// Declares a typed test suite over every built policy, named Suite/seq, Suite/par, Suite/gpu.
#define UNISPH_POLICY_TEST_SUITE(Suite)                  \
  template <class P>                                     \
  class Suite : public ::unisph::testing::PolicyTest<P> {}; \
  TYPED_TEST_SUITE(Suite, ::unisph::testing::Policies, ::unisph::testing::PolicyNames)
