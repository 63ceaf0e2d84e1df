// The CUDA backend's host services (see include/unisph/exec/backend/cuda/runtime.hpp).
// Compiled as CUDA when the backend is built; otherwise every entry point reports that the
// device is not available.

#include "unisph/exec/backend/cuda/runtime.hpp"

#include <algorithm>
#include <map>
#include <mutex>
#include <string>
#include <unordered_map>

#include "unisph/core/error.hpp"
#include "unisph/exec/policy.hpp"

#if UNISPH_HAS_CUDA
#include <cuda.h>
#include <cuda_runtime.h>
#endif

namespace unisph::cuda {

void require_device() {
  static const bool ok = policy_available(PolicyKind::device);
  if (!ok) require_policy(PolicyKind::device);  // throws with the reason
}

#if UNISPH_HAS_CUDA

namespace {
std::string bytes_text(std::size_t bytes) { return std::to_string(bytes) + " bytes"; }

// Every live allocation with what it served, for device_memory_use(): allocations are rare in
// a run's steady state (variables keep their storage), so a map under a lock costs nothing.
struct Ledger {
  std::mutex mutex;
  std::unordered_map<void*, std::pair<std::size_t, std::string>> live;
  std::uint64_t bytes = 0, peak = 0;
};
Ledger& ledger() {
  static Ledger l;
  return l;
}
// "resizing variable 'Position' (10 elements of 24 bytes) to 12 elements" -> "variable 'Position'".
std::string group_of(std::string_view what) {
  if (what.rfind("resizing ", 0) == 0) what.remove_prefix(9);
  const std::size_t paren = what.find(" (");
  return std::string(paren == std::string_view::npos ? what : what.substr(0, paren));
}
}  // namespace

std::vector<AllocationGroup> live_allocations() {
  Ledger& l = ledger();
  std::lock_guard lock(l.mutex);
  std::map<std::string, AllocationGroup> groups;
  for (const auto& [ptr, entry] : l.live) {
    AllocationGroup& g = groups[entry.second];
    g.what = entry.second;
    g.bytes += entry.first;
    ++g.count;
  }
  std::vector<AllocationGroup> out;
  for (auto& [name, g] : groups) out.push_back(std::move(g));
  std::stable_sort(out.begin(), out.end(), [](const AllocationGroup& a, const AllocationGroup& b) { return a.bytes > b.bytes; });
  return out;
}
std::uint64_t allocated_bytes() {
  std::lock_guard lock(ledger().mutex);
  return ledger().bytes;
}
std::uint64_t allocated_peak_bytes() {
  std::lock_guard lock(ledger().mutex);
  return ledger().peak;
}

int select_device_ordinal(int ordinal) {
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess || count == 0) {
    cudaGetLastError();
    return -1;
  }
  const int chosen = ((ordinal % count) + count) % count;
  check(cudaSetDevice(chosen), "cudaSetDevice");
  return chosen;
}

std::uint64_t free_device_bytes() {
  std::size_t free = 0, total = 0;
  if (cudaMemGetInfo(&free, &total) != cudaSuccess) {
    cudaGetLastError();
    return 0;
  }
  return free;
}

void describe_device(ExecutionInfo& info) {
  info.cuda_built = true;
  int count = 0;
  const cudaError_t err = cudaGetDeviceCount(&count);
  if (err != cudaSuccess || count == 0) {
    cudaGetLastError();
    info.device_present = false;
    info.device_unavailable_reason =
        err != cudaSuccess ? std::string("no usable CUDA GPU: ") + cudaGetErrorString(err) : "no CUDA GPU on this machine";
    return;
  }
  int current = 0;
  if (cudaGetDevice(&current) != cudaSuccess) current = 0;
  cudaDeviceProp prop{};
  if (cudaGetDeviceProperties(&prop, current) != cudaSuccess) {
    cudaGetLastError();
    info.device_unavailable_reason = "the CUDA GPU could not be queried";
    return;
  }
  info.device_present = true;
  info.device_name = prop.name;
  info.device_multiprocessors = prop.multiProcessorCount;
  info.device_memory_gib = static_cast<double>(prop.totalGlobalMem) / (1024.0 * 1024.0 * 1024.0);
  if (prop.major < 7) {
    info.device_present = false;
    info.device_unavailable_reason = std::string("the GPU ") + prop.name + " (compute capability " +
                                     std::to_string(prop.major) + "." + std::to_string(prop.minor) +
                                     ") is older than this build supports";
  }
}

void check(int code, std::string_view what) {
  if (code == cudaSuccess) return;
  const auto err = static_cast<cudaError_t>(code);
  throw DeviceError(std::string(what) + ": " + cudaGetErrorName(err) + ": " + cudaGetErrorString(err));
}

void check_launch(std::string_view what, std::size_t items) {
  const cudaError_t err = cudaGetLastError();
  if (err != cudaSuccess)
    check(err, "launch of " + std::string(what) + " over " + std::to_string(items) + " items");
}

namespace {
thread_local bool on_side = false;  // SideStreamScope
}

void* stream_handle() { return on_side ? side_stream_handle() : main_stream_handle(); }
bool on_side_stream() { return on_side; }
SideStreamScope::SideStreamScope() : previous_(on_side) { on_side = true; }
SideStreamScope::~SideStreamScope() { on_side = previous_; }

void* main_stream_handle() {
  static cudaStream_t stream = [] {
    require_device();
    cudaStream_t s{};
    // Non-blocking: unisph's work does not serialise with the legacy default stream of other libraries.
    check(cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking), "creating the unisph CUDA stream");
    return s;
  }();
  return stream;
}

static cudaStream_t stream() { return static_cast<cudaStream_t>(stream_handle()); }
static cudaStream_t main_stream() { return static_cast<cudaStream_t>(main_stream_handle()); }

void* side_stream_handle() {
  static cudaStream_t side = [] {
    require_device();
    int least = 0, greatest = 0;
    check(cudaDeviceGetStreamPriorityRange(&least, &greatest), "reading the stream priorities");
    cudaStream_t s{};
    check(cudaStreamCreateWithPriority(&s, cudaStreamNonBlocking, greatest), "creating the unisph side stream");
    return s;
  }();
  return side;
}

namespace {
// Two events that order one stream after the other (reused: a wait takes the event's state when
// it is queued).
cudaEvent_t ordering_event(int which) {
  static cudaEvent_t events[2] = {[] {
                                    cudaEvent_t e{};
                                    check(cudaEventCreateWithFlags(&e, cudaEventDisableTiming), "creating an event");
                                    return e;
                                  }(),
                                  [] {
                                    cudaEvent_t e{};
                                    check(cudaEventCreateWithFlags(&e, cudaEventDisableTiming), "creating an event");
                                    return e;
                                  }()};
  return events[which];
}
struct TimeMarks {
  std::vector<cudaEvent_t> events;
  std::size_t used = 0;
};
TimeMarks& time_marks() {
  static TimeMarks marks;
  return marks;
}
}  // namespace

void side_stream_wait_main(std::string_view what) {
  const cudaEvent_t e = ordering_event(0);
  check(cudaEventRecord(e, main_stream()), std::string(what) + ": recording the main stream's event");
  check(cudaStreamWaitEvent(static_cast<cudaStream_t>(side_stream_handle()), e, 0),
        std::string(what) + ": the side stream waiting for the main stream");
}

void main_wait_side_stream(std::string_view what) {
  const cudaEvent_t e = ordering_event(1);
  check(cudaEventRecord(e, static_cast<cudaStream_t>(side_stream_handle())),
        std::string(what) + ": recording the side stream's event");
  check(cudaStreamWaitEvent(main_stream(), e, 0), std::string(what) + ": the main stream waiting for the side stream");
}

int mark_time() {
  TimeMarks& m = time_marks();
  if (m.used == m.events.size()) {
    cudaEvent_t e{};
    check(cudaEventCreate(&e), "creating a timing event");
    m.events.push_back(e);
  }
  check(cudaEventRecord(m.events[m.used], stream()), "recording a timing event");
  return static_cast<int>(m.used++);
}

double seconds_between(int a, int b) {
  TimeMarks& m = time_marks();
  check(cudaEventSynchronize(m.events[std::size_t(b)]), "waiting for a timing event");
  float ms = 0;
  check(cudaEventElapsedTime(&ms, m.events[std::size_t(a)], m.events[std::size_t(b)]), "reading a timing event");
  return 1e-3 * double(ms);
}

void clear_time_marks() { time_marks().used = 0; }

int multiprocessor_count() {
  static const int count = [] {
    require_device();
    int device = 0, sms = 0;
    check(cudaGetDevice(&device), "cudaGetDevice");
    check(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device), "reading the multiprocessor count");
    return sms;
  }();
  return count;
}

void* allocate(std::size_t bytes, std::string_view what) {
  require_device();
  if (bytes == 0) return nullptr;
  void* ptr = nullptr;
  const cudaError_t err = cudaMalloc(&ptr, bytes);
  if (err != cudaSuccess) {
    cudaGetLastError();  // clear the sticky-free error so later calls are not blamed
    check(err, "cudaMalloc of " + bytes_text(bytes) + " for " + std::string(what));
  }
  Ledger& l = ledger();
  std::lock_guard lock(l.mutex);
  l.live.emplace(ptr, std::make_pair(bytes, group_of(what)));
  l.bytes += bytes;
  l.peak = std::max(l.peak, l.bytes);
  return ptr;
}

void deallocate(void* ptr) noexcept {
  if (!ptr) return;
  cudaFree(ptr);
  Ledger& l = ledger();
  std::lock_guard lock(l.mutex);
  const auto at = l.live.find(ptr);
  if (at == l.live.end()) return;
  l.bytes -= at->second.first;
  l.live.erase(at);
}

void copy_to_device(void* dst, const void* src, std::size_t bytes, std::string_view what) {
  if (bytes == 0) return;
  check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyHostToDevice, stream()),
        "copy of " + bytes_text(bytes) + " to the device for " + std::string(what));
}

void copy_to_host(void* dst, const void* src, std::size_t bytes, std::string_view what) {
  if (bytes == 0) return;
  const std::string label = "copy of " + bytes_text(bytes) + " to the host for " + std::string(what);
  check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyDeviceToHost, stream()), label);
  check(cudaStreamSynchronize(stream()), label);
}

void copy_on_device(void* dst, const void* src, std::size_t bytes, std::string_view what) {
  if (bytes == 0) return;
  check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyDeviceToDevice, stream()),
        "device-to-device copy of " + bytes_text(bytes) + " for " + std::string(what));
}

void fill_zero(void* dst, std::size_t bytes, std::string_view what) {
  if (bytes == 0) return;
  check(cudaMemsetAsync(dst, 0, bytes, stream()), "zero fill of " + bytes_text(bytes) + " for " + std::string(what));
}

void synchronize(std::string_view what) { check(cudaStreamSynchronize(stream()), std::string(what)); }

namespace {
// The workspace (runtime.hpp) on CUDA's virtual memory management: cuMemAddressReserve once,
// then cuMemCreate / cuMemMap / cuMemSetAccess for each growth. The driver's entry points come
// through the runtime (cudaGetDriverEntryPointByVersion), so nothing links libcuda directly.
struct DriverCalls {
  decltype(&cuMemGetAllocationGranularity) granularity = nullptr;
  decltype(&cuMemAddressReserve) reserve = nullptr;
  decltype(&cuMemCreate) create = nullptr;
  decltype(&cuMemMap) map = nullptr;
  decltype(&cuMemSetAccess) set_access = nullptr;
  decltype(&cuMemRelease) release = nullptr;
  decltype(&cuDeviceGetAttribute) attribute = nullptr;
};

template <class F>
void driver_entry(const char* name, F& fn) {
  void* p = nullptr;
  cudaDriverEntryPointQueryResult found{};
  check(cudaGetDriverEntryPointByVersion(name, &p, 12000, cudaEnableDefault, &found),
        std::string("looking up the CUDA driver's ") + name);
  if (found != cudaDriverEntryPointSuccess || !p)
    throw DeviceError(std::string("the CUDA driver has no ") + name + " (the device workspace needs CUDA 12 or later)");
  fn = reinterpret_cast<F>(p);
}

void check_driver(CUresult r, const std::string& what) {
  if (r == CUDA_SUCCESS) return;
  throw DeviceError(what + ": CUDA driver error " + std::to_string(int(r)) +
                    (r == CUDA_ERROR_OUT_OF_MEMORY ? " (out of memory)" : ""));
}

struct Workspace {
  std::mutex mutex;
  DriverCalls cu;
  CUdeviceptr base = 0;
  std::size_t reserved = 0;   // address range
  std::size_t mapped = 0;     // backed by memory, from base
  std::size_t top = 0;        // taken, from base
  std::size_t granularity = 0;
  CUmemAllocationProp prop{};

  void start() {
    require_device();
    driver_entry("cuMemGetAllocationGranularity", cu.granularity);
    driver_entry("cuMemAddressReserve", cu.reserve);
    driver_entry("cuMemCreate", cu.create);
    driver_entry("cuMemMap", cu.map);
    driver_entry("cuMemSetAccess", cu.set_access);
    driver_entry("cuMemRelease", cu.release);
    driver_entry("cuDeviceGetAttribute", cu.attribute);
    int device = 0;
    check(cudaGetDevice(&device), "cudaGetDevice");
    int supported = 0;
    check_driver(cu.attribute(&supported, CU_DEVICE_ATTRIBUTE_VIRTUAL_MEMORY_MANAGEMENT_SUPPORTED, device),
                 "asking for virtual memory management");
    if (!supported) throw DeviceError("the GPU does not support virtual memory management, which the device workspace uses");
    prop.type = CU_MEM_ALLOCATION_TYPE_PINNED;
    prop.location.type = CU_MEM_LOCATION_TYPE_DEVICE;
    prop.location.id = device;
    check_driver(cu.granularity(&granularity, &prop, CU_MEM_ALLOC_GRANULARITY_RECOMMENDED),
                 "asking the device workspace's granularity");
    std::size_t free = 0, total = 0;
    check(cudaMemGetInfo(&free, &total), "cudaMemGetInfo");
    // The whole device's size: the stack can never need more addresses than there is memory.
    reserved = (total + granularity - 1) / granularity * granularity;
    check_driver(cu.reserve(&base, reserved, 0, 0, 0), "reserving " + bytes_text(reserved) + " of addresses for the device workspace");
  }

  // Backs [0, need) with memory (never shrinks).
  void cover(std::size_t need, std::string_view what) {
    if (need <= mapped) return;
    if (!base) start();
    // Headroom of 1/32, as a variable's growth, and whole granules.
    std::size_t grow = need - mapped + need / 32;
    grow = (grow + granularity - 1) / granularity * granularity;
    if (mapped + grow > reserved) grow = reserved - mapped;
    if (mapped + grow < need)
      throw DeviceError("the device workspace would need " + bytes_text(need) + " for " + std::string(what) +
                        ", more than the device's " + bytes_text(reserved));
    const std::string label = "mapping " + bytes_text(grow) + " more device workspace for " + std::string(what) +
                              " (" + bytes_text(mapped) + " mapped)";
    CUmemGenericAllocationHandle handle{};
    check_driver(cu.create(&handle, grow, &prop, 0), label);
    const CUresult mapped_ok = cu.map(base + mapped, grow, 0, handle, 0);
    // The mapping holds the memory from here on; the handle is not needed (nothing is unmapped).
    cu.release(handle);
    check_driver(mapped_ok, label);
    CUmemAccessDesc access{};
    access.location = prop.location;
    access.flags = CU_MEM_ACCESS_FLAGS_PROT_READWRITE;
    check_driver(cu.set_access(base + mapped, grow, &access, 1), label);
    Ledger& l = ledger();
    std::lock_guard lock(l.mutex);
    l.live.emplace(reinterpret_cast<void*>(base + mapped), std::make_pair(grow, std::string("device workspace")));
    l.bytes += grow;
    l.peak = std::max(l.peak, l.bytes);
    mapped += grow;
  }
};
Workspace& workspace() {
  static Workspace w;
  return w;
}
constexpr std::size_t workspace_alignment = 256;
}  // namespace

void* workspace_take(std::size_t bytes, std::string_view what) {
  Workspace& w = workspace();
  std::lock_guard lock(w.mutex);
  const std::size_t size = (bytes + workspace_alignment - 1) / workspace_alignment * workspace_alignment;
  w.cover(w.top + size, what);
  void* p = reinterpret_cast<void*>(w.base + w.top);
  w.top += size;
  return p;
}

std::size_t workspace_mark() {
  Workspace& w = workspace();
  std::lock_guard lock(w.mutex);
  return w.top;
}

void workspace_release(std::size_t mark) {
  Workspace& w = workspace();
  std::lock_guard lock(w.mutex);
  if (mark <= w.top) w.top = mark;
}

void* scratch(std::size_t bytes, std::string_view what) {
  Workspace& w = workspace();
  std::lock_guard lock(w.mutex);
  w.cover(w.top + std::max<std::size_t>(bytes, 1), what);
  return reinterpret_cast<void*>(w.base + w.top);
}

void* pinned_result_buffer() {
  static void* buffer = [] {
    require_device();
    void* p = nullptr;
    check(cudaHostAlloc(&p, pinned_result_bytes, cudaHostAllocMapped), "cudaHostAlloc of the reduction result buffer");
    return p;
  }();
  return buffer;
}

#else  // no CUDA backend in this build

int select_device_ordinal(int) { return -1; }
std::uint64_t free_device_bytes() { return 0; }

void describe_device(ExecutionInfo& info) {
  info.cuda_built = false;
  info.device_present = false;
  info.device_unavailable_reason =
      "this unisph was built without the CUDA backend (configure with -DUNISPH_ENABLE_CUDA=ON on a machine with nvcc)";
}

[[noreturn]] static void unavailable() { require_policy(PolicyKind::device); throw PolicyUnavailable("device"); }
void check(int, std::string_view) {}
void check_launch(std::string_view, std::size_t) {}
void* stream_handle() { unavailable(); }
void* main_stream_handle() { unavailable(); }
bool on_side_stream() { return false; }
SideStreamScope::SideStreamScope() : previous_(false) {}
SideStreamScope::~SideStreamScope() = default;
void* side_stream_handle() { unavailable(); }
void side_stream_wait_main(std::string_view) { unavailable(); }
void main_wait_side_stream(std::string_view) { unavailable(); }
int mark_time() { unavailable(); }
double seconds_between(int, int) { unavailable(); }
void clear_time_marks() {}
void* pinned_result_buffer() { unavailable(); }
int multiprocessor_count() { unavailable(); }
void* allocate(std::size_t, std::string_view) { unavailable(); }
void deallocate(void*) noexcept {}
std::vector<AllocationGroup> live_allocations() { return {}; }
std::uint64_t allocated_bytes() { return 0; }
std::uint64_t allocated_peak_bytes() { return 0; }
void copy_to_device(void*, const void*, std::size_t, std::string_view) { unavailable(); }
void copy_to_host(void*, const void*, std::size_t, std::string_view) { unavailable(); }
void copy_on_device(void*, const void*, std::size_t, std::string_view) { unavailable(); }
void fill_zero(void*, std::size_t, std::string_view) { unavailable(); }
void synchronize(std::string_view) {}
void* scratch(std::size_t, std::string_view) { unavailable(); }
void* workspace_take(std::size_t, std::string_view) { unavailable(); }
std::size_t workspace_mark() { return 0; }
void workspace_release(std::size_t) {}

#endif

}  // namespace unisph::cuda
