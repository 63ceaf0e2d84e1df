// Host/device coherence of variables (see include/unisph/memory/variable_base.hpp).

#include "unisph/memory/variable_base.hpp"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <new>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "unisph/core/error.hpp"
#include "unisph/exec/backend/cuda/runtime.hpp"

namespace unisph {

namespace {

std::uint64_t next_stamp() {
  static std::atomic<std::uint64_t> counter{1};
  return counter.fetch_add(1, std::memory_order_relaxed);
}

constexpr int host_side = static_cast<int>(MemorySpace::host);
constexpr int device_side = static_cast<int>(MemorySpace::device);

void* allocate_host(std::size_t bytes, std::size_t alignment) {
  if (bytes == 0) return nullptr;
  return ::operator new(bytes, std::align_val_t(std::max<std::size_t>(alignment, 64)));
}
void free_host(void* ptr, std::size_t alignment) {
  if (ptr) ::operator delete(ptr, std::align_val_t(std::max<std::size_t>(alignment, 64)));
}

// Zeros a new host array. Large ones are zeroed by the host threads in chunks: zeroing is the
// first touch of the pages, and page faults taken on one thread were a serial part of the
// parallel level-set build (a 203 MB phi array at N = 1024). Under `seq` the host threads are
// still there; only the zeroing uses them.
void zero_host(void* ptr, std::size_t bytes) {
  constexpr std::size_t chunk = std::size_t(1) << 20;
  if (bytes < 8 * chunk) {
    std::memset(ptr, 0, bytes);
    return;
  }
  char* base = static_cast<char*>(ptr);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, (bytes + chunk - 1) / chunk), [&](const auto& r) {
    const std::size_t first = r.begin() * chunk, last = std::min(bytes, r.end() * chunk);
    std::memset(base + first, 0, last - first);
  });
}

}  // namespace

VariableBase::VariableBase(std::string name, std::size_t element_size, std::size_t element_alignment, Index count)
    : name_(std::move(name)), element_size_(element_size), alignment_(element_alignment), count_(count) {
  // Nothing is allocated yet: the contents are zero, held by neither side (see prepare).
  stamp_[host_side] = next_stamp();
  stamp_[device_side] = next_stamp();
}

VariableBase::~VariableBase() {
  free_host(host_, alignment_);
  cuda::deallocate(device_);
}

std::string VariableBase::describe() const {
  return "variable '" + name_ + "' (" + std::to_string(count_) + " elements of " + std::to_string(element_size_) +
         " bytes)";
}

void VariableBase::ensure_host_allocation() {
  if (host_allocated_) return;
  host_ = allocate_host(bytes(), alignment_);
  host_capacity_ = bytes();
  // The host copy starts as the variable's zeros; if the device is current it is overwritten.
  if (host_) zero_host(host_, bytes());
  host_allocated_ = true;
  stamp_[host_side] = next_stamp();
}

void VariableBase::ensure_device_allocation() {
  if (device_allocated_) return;
  device_ = cuda::allocate(bytes(), describe());
  device_capacity_ = bytes();
  device_allocated_ = true;
  stamp_[device_side] = next_stamp();
}

void VariableBase::copy_host_to_device() {
  if (!host_allocated_) {
    // The host side holds the initial zeros only implicitly: set them, copy nothing.
    cuda::fill_zero(device_, bytes(), describe());
    return;
  }
  cuda::copy_to_device(device_, host_, bytes(), describe());
  ++copies_to_device_;
}

void VariableBase::copy_device_to_host() {
  cuda::copy_to_host(host_, device_, bytes(), describe());
  ++copies_to_host_;
}

void* VariableBase::prepare(MemorySpace space, Access mode) {
  const bool needs_contents = mode != Access::write;
  const bool modifies = mode != Access::read;
  if (space == MemorySpace::host) {
    ensure_host_allocation();
    if (needs_contents && !current_[host_side]) copy_device_to_host();
    current_[host_side] = true;
    if (modifies) current_[device_side] = false;
    return host_;
  }
  ensure_device_allocation();
  if (needs_contents && !current_[device_side]) copy_host_to_device();
  current_[device_side] = true;
  if (modifies) current_[host_side] = false;
  return device_;
}

void VariableBase::resize_elements(Index count) {
  if (count == count_) return;
  const std::size_t new_bytes = count * element_size_;
  const std::size_t kept = std::min(bytes(), new_bytes);
  const std::string what = "resizing " + describe() + " to " + std::to_string(count) + " elements";

  // A current side keeps its allocation where the new size fits in it (new elements zeroed);
  // otherwise it moves to one 1/32 larger than asked, so that sizes that drift up step by step
  // allocate rarely. Everything is allocated before anything changes, so that a failure leaves
  // the variable as it was.
  const bool keep_device = device_allocated_ && current_[device_side];
  const bool keep_host = host_allocated_ && current_[host_side];
  const bool device_fits = keep_device && new_bytes <= device_capacity_;
  const bool host_fits = keep_host && new_bytes <= host_capacity_;
  const std::size_t grown = new_bytes + new_bytes / 32;
  void* device = keep_device && !device_fits ? cuda::allocate(grown, what) : nullptr;
  void* host = nullptr;
  try {
    host = keep_host && !host_fits ? allocate_host(grown, alignment_) : nullptr;
  } catch (...) {
    cuda::deallocate(device);
    throw;
  }

  if (host_fits) {
    zero_host(static_cast<char*>(host_) + kept, new_bytes - kept);
  } else {
    if (host) {
      if (kept) std::memcpy(host, host_, kept);
      zero_host(static_cast<char*>(host) + kept, new_bytes - kept);
    }
    // A stale copy is dropped: the next access on its side allocates it and copies.
    free_host(host_, alignment_);
    host_ = host;
    host_allocated_ = keep_host;
    host_capacity_ = host ? grown : 0;
  }
  if (device_fits) {
    cuda::fill_zero(static_cast<char*>(device_) + kept, new_bytes - kept, what);
  } else {
    if (keep_device) {
      cuda::copy_on_device(device, device_, kept, what);
      cuda::fill_zero(static_cast<char*>(device) + kept, new_bytes - kept, what);
    }
    cuda::deallocate(device_);
    device_ = device;
    device_allocated_ = keep_device;
    device_capacity_ = device ? grown : 0;
  }
  stamp_[host_side] = next_stamp();
  stamp_[device_side] = next_stamp();
  count_ = count;
}

}  // namespace unisph
