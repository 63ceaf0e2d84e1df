#pragma once
// Execution policies: the type picks the backend at compile time; the instances `seq`, `par`
// and `par_device` are what users pass to the algorithms.
//
// One mapping of names everywhere:
//   C++ policy      command line        ctest label
//   seq             --policy seq        seq
//   par             --policy par        par
//   par_device      --policy device     gpu

#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "unisph/core/config.hpp"
#include "unisph/core/error.hpp"
#include "unisph/memory/space.hpp"

namespace unisph {

struct SequencedPolicy {
  static constexpr MemorySpace space = MemorySpace::host;
  static constexpr std::string_view name = "seq";
  static constexpr std::string_view test_label = "seq";
};
struct ParallelPolicy {
  static constexpr MemorySpace space = MemorySpace::host;
  static constexpr std::string_view name = "par";
  static constexpr std::string_view test_label = "par";
};
struct ParallelDevicePolicy {
  static constexpr MemorySpace space = MemorySpace::device;
  static constexpr std::string_view name = "device";
  static constexpr std::string_view test_label = "gpu";
};

inline constexpr SequencedPolicy seq{};
inline constexpr ParallelPolicy par{};
inline constexpr ParallelDevicePolicy par_device{};

template <class P>
inline constexpr bool is_execution_policy_v =
    std::is_same_v<std::remove_cvref_t<P>, SequencedPolicy> || std::is_same_v<std::remove_cvref_t<P>, ParallelPolicy> ||
    std::is_same_v<std::remove_cvref_t<P>, ParallelDevicePolicy>;

template <class P>
concept ExecutionPolicy = is_execution_policy_v<P>;

// Run-time name of a policy, for command lines and case files.
enum class PolicyKind { seq, par, device };

// Makes GPU `ordinal` modulo the GPUs present the device of this process (one rank per GPU:
// the rank's number on its node). Call it before anything else touches the GPU; returns the
// ordinal chosen, or -1 where no GPU is present or the build has no CUDA backend.
int select_device(int ordinal);

// The free memory of this process's GPU now (cudaMemGetInfo; it makes the GPU's context where
// none exists); 0 where there is no GPU or the build has no CUDA backend. A run's device memory
// is the free memory before it less the least free memory seen during it.
std::uint64_t device_free_bytes();

// The device memory unisph itself allocated (variables, scratch), grouped by what each block
// served ("variable 'Position'", "scratch storage of ..."), largest first; and the most held
// at once. The rest of a run's device memory is the libraries' (NCCL's buffers, CUDA's
// runtime). Empty and 0 where there is no GPU.
struct DeviceMemoryGroup {
  std::string what;
  std::uint64_t bytes = 0;
  std::uint64_t blocks = 0;
};
struct DeviceMemoryUse {
  std::uint64_t bytes = 0, peak_bytes = 0;
  std::vector<DeviceMemoryGroup> groups;
};
DeviceMemoryUse device_memory_use();

std::string_view to_string(PolicyKind kind);
// Parses "seq", "par" or "device"; throws unisph::Error naming the accepted words otherwise.
PolicyKind parse_policy(std::string_view name);

// What this build and this machine offer.
struct ExecutionInfo {
  bool cuda_built = false;         // the CUDA backend is compiled into this unisph
  bool device_present = false;     // ... and a usable CUDA GPU was found
  std::string device_name;         // e.g. "NVIDIA H100 80GB HBM3"
  std::string device_unavailable_reason;  // why par_device cannot run, when it cannot
  int device_multiprocessors = 0;
  double device_memory_gib = 0.0;
  std::vector<PolicyKind> available;  // the policies that can run here, in the order seq, par, device
};

// Queried once (the CUDA runtime is asked at most once per process).
const ExecutionInfo& execution_info();

bool policy_available(PolicyKind kind);

// Throws PolicyUnavailable with the reason when `kind` cannot run on this build and machine.
void require_policy(PolicyKind kind);

// Threads the par policy uses now.
int host_threads();

// Limits the threads of the par policy for the rest of the process (0: all hardware threads).
void set_host_threads(int threads);

// Calls f(seq), f(par) or f(par_device) for a policy chosen at run time. Checks availability
// first, so an unavailable device is an exception, never a silent fallback.
template <class F>
decltype(auto) visit_policy(PolicyKind kind, F&& f) {
  require_policy(kind);
  switch (kind) {
    case PolicyKind::seq:
      return f(seq);
    case PolicyKind::par:
      return f(par);
    case PolicyKind::device:
#if UNISPH_HAS_CUDA && defined(__CUDACC__)
      return f(par_device);
#else
      break;
#endif
  }
  // Reached only in translation units not compiled by nvcc, which cannot launch device kernels.
  throw PolicyUnavailable(
      "the device policy was asked for from code not compiled as CUDA; compile this source with nvcc "
      "(unisph_kernel_sources in CMake)");
}

}  // namespace unisph
