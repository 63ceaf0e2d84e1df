// Run-time side of the execution policies: names, what this machine offers, thread count.

#include "unisph/exec/policy.hpp"

#include <memory>
#include <mutex>
#include <string>

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include "unisph/core/error.hpp"
#include "unisph/exec/backend/cuda/runtime.hpp"

namespace unisph {

std::string_view to_string(PolicyKind kind) {
  switch (kind) {
    case PolicyKind::seq:
      return SequencedPolicy::name;
    case PolicyKind::par:
      return ParallelPolicy::name;
    case PolicyKind::device:
      return ParallelDevicePolicy::name;
  }
  return "?";
}

PolicyKind parse_policy(std::string_view name) {
  if (name == SequencedPolicy::name) return PolicyKind::seq;
  if (name == ParallelPolicy::name) return PolicyKind::par;
  if (name == ParallelDevicePolicy::name) return PolicyKind::device;
  throw Error("unknown execution policy '" + std::string(name) + "': expected seq, par or device");
}

namespace {
std::unique_ptr<tbb::global_control> thread_limit;
std::mutex thread_limit_mutex;
}  // namespace

void set_host_threads(int threads) {
  std::lock_guard lock(thread_limit_mutex);
  thread_limit.reset();
  if (threads > 0)
    thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                         static_cast<std::size_t>(threads));
}

int host_threads() {
  return static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

int select_device(int ordinal) { return cuda::select_device_ordinal(ordinal); }
std::uint64_t device_free_bytes() { return cuda::free_device_bytes(); }
DeviceMemoryUse device_memory_use() {
  DeviceMemoryUse use{cuda::allocated_bytes(), cuda::allocated_peak_bytes(), {}};
  for (cuda::AllocationGroup& g : cuda::live_allocations()) use.groups.push_back({std::move(g.what), g.bytes, g.count});
  return use;
}

const ExecutionInfo& execution_info() {
  static ExecutionInfo info = [] {
    ExecutionInfo i;
    cuda::describe_device(i);
    i.available = {PolicyKind::seq, PolicyKind::par};
    if (i.cuda_built && i.device_present) i.available.push_back(PolicyKind::device);
    return i;
  }();
  return info;
}

bool policy_available(PolicyKind kind) {
  if (kind != PolicyKind::device) return true;
  const ExecutionInfo& info = execution_info();
  return info.cuda_built && info.device_present;
}

void require_policy(PolicyKind kind) {
  if (policy_available(kind)) return;
  throw PolicyUnavailable("the device policy (--policy device) cannot run: " +
                          execution_info().device_unavailable_reason);
}

}  // namespace unisph
