// A kernel that faults on the device becomes a DeviceError naming where it was found; launch
// errors are checked at the launch. A device fault leaves the CUDA context unusable, so this
// program holds nothing else and runs on its own.
#include <string>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"

namespace {
using namespace unisph;

struct FaultOnDevice {
  View<double> v;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
#if defined(__CUDA_ARCH__)
    if (i == 7) __trap();
#endif
    v[i] = 1.0;
  }
};

UNISPH_POLICY_TEST_SUITE(DeviceFault);

TYPED_TEST(DeviceFault, KernelFaultBecomesAnException) {
  DiscreteVariable<double> v("FaultyField", 1000);
  particle_for(this->policy, 1000, FaultOnDevice{v.write(this->policy)});
  if constexpr (decltype(this->policy)::space == MemorySpace::host) {
    EXPECT_EQ(v.to_vector()[7], 1.0);  // on the host the same kernel simply runs
  } else {
    try {
      fence(this->policy);
      FAIL() << "expected a DeviceError";
    } catch (const unisph::DeviceError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("fence(par_device)"), std::string::npos) << message;
      EXPECT_NE(message.find("cudaError"), std::string::npos) << message;
    }
  }
}

}  // namespace
