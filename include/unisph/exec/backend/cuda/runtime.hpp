#pragma once
// Host-side services of the CUDA backend: device memory, copies, the stream every launch goes
// to, and scratch storage for the algorithms. Declared here without CUDA headers so that
// code compiled by the host compiler (variables, the program) can call them; implemented in
// src/cuda/runtime.cpp. In a build without CUDA every call throws PolicyUnavailable.
//
// Every failure becomes a DeviceError whose message names the operation, what it served
// (a variable's name, an algorithm) and the size, then CUDA's own words.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace unisph {
struct ExecutionInfo;
}

namespace unisph::cuda {

// Fills the device fields of `info` (built, present, name, reason when absent). Never throws.
void describe_device(ExecutionInfo& info);
int select_device_ordinal(int ordinal);  // select_device() (exec/policy.hpp)
std::uint64_t free_device_bytes();       // device_free_bytes() (exec/policy.hpp)

// Throws PolicyUnavailable (with the reason) unless the CUDA backend is built and a GPU is present.
void require_device();

// cudaStream_t of the stream unisph's launches and copies go to: the main stream (created on
// first use), or the side stream on a thread within a SideStreamScope.
void* stream_handle();
void* main_stream_handle();

// The side stream: a second stream, of higher priority, for transfers that overlap the main
// stream's work (a halo's exchange beside the interior particles' interactions); its kernels
// start between the main stream's blocks. side_stream_wait_main(): work queued on the side
// stream from now on starts after everything queued on the main stream so far;
// main_wait_side_stream(): the other way round. Neither blocks the host.
void* side_stream_handle();
void side_stream_wait_main(std::string_view what);
void main_wait_side_stream(std::string_view what);
// While one lives, this thread's launches and copies go to the side stream (work that runs beside
// the main stream's: a halo's unpacking and the border particles' pass after its exchange).
class SideStreamScope {
 public:
  SideStreamScope();
  ~SideStreamScope();
  SideStreamScope(const SideStreamScope&) = delete;
  SideStreamScope& operator=(const SideStreamScope&) = delete;

 private:
  bool previous_;
};
bool on_side_stream();

// Timing marks on the main stream (CUDA events, which do not stop the host): mark_time() returns
// a mark's number; seconds_between(a, b) waits for mark b and gives the device time from a to b.
// clear_time_marks() recycles every mark taken (call it once their times are read).
int mark_time();
double seconds_between(int a, int b);
void clear_time_marks();

int multiprocessor_count();

void* allocate(std::size_t bytes, std::string_view what);
void deallocate(void* ptr) noexcept;

// What allocate() holds now, by what it served (a variable's name, a scratch's user), and
// the most it held at once: device_memory_use() (exec/policy.hpp).
struct AllocationGroup {
  std::string what;
  std::uint64_t bytes = 0;
  std::uint64_t count = 0;
};
std::vector<AllocationGroup> live_allocations();
std::uint64_t allocated_bytes();
std::uint64_t allocated_peak_bytes();

// Host -> device. Asynchronous with respect to the host where CUDA allows it.
void copy_to_device(void* dst, const void* src, std::size_t bytes, std::string_view what);
// Device -> host. Returns when the data has arrived (it waits for earlier work on the stream).
void copy_to_host(void* dst, const void* src, std::size_t bytes, std::string_view what);
// Device -> device, asynchronous.
void copy_on_device(void* dst, const void* src, std::size_t bytes, std::string_view what);
void fill_zero(void* dst, std::size_t bytes, std::string_view what);
// Waits for every launch and copy issued so far.
void synchronize(std::string_view what);

// The device workspace: one address range, reserved once, behind which physical memory is mapped
// as it is needed and kept; used as a stack. Buffers that live only within one phase of a step
// (a sort's keys and permutation, a cell list's run arrays, a plan's lists) are taken from its top
// and released together at the phase's end (exec/workspace.hpp: WorkspaceScope), and the
// algorithms' temporaries lie above them. So the device holds the most that one phase needs at
// once, not the sum of every phase's buffers. Growing maps more memory behind the same addresses:
// a block taken stays where it is while the stack grows above it. Stream order keeps a released
// block's last use ahead of its next one (the main stream runs every launch and copy that uses
// it; the side stream's work, a halo's unpacking and the border particles' pass, takes none).
//
// workspace_take: `bytes` (rounded up to 256) at the top, until released; workspace_mark: the
// top now; workspace_release(mark): the top back to `mark` (the blocks taken since). Throws
// DeviceError where the device has no memory left to map, naming `what`.
void* workspace_take(std::size_t bytes, std::string_view what);
std::size_t workspace_mark();
void workspace_release(std::size_t mark);

// Temporary storage of the algorithms (CUB temporaries, reduction partials, sort double
// buffers): the workspace above its top. Valid until the next call to scratch() or
// workspace_take(); stream order keeps one algorithm's use from overlapping the next one's.
void* scratch(std::size_t bytes, std::string_view what);

// 256 bytes of pinned host memory that device kernels can write directly (mapped): a
// reduction's final pass writes its result there, so returning it costs one stream
// synchronisation and no copy.
void* pinned_result_buffer();
inline constexpr std::size_t pinned_result_bytes = 256;

// Throws DeviceError for a failed CUDA call: "<what>: <CUDA error name>: <description>".
void check(int cuda_error_code, std::string_view what);
// Checks the launch that just happened (cudaGetLastError, no waiting).
void check_launch(std::string_view what, std::size_t items);

}  // namespace unisph::cuda
