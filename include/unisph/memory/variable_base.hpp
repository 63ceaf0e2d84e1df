#pragma once
// The untyped core of every variable: a host copy and (from its first device access on) a
// device copy of the same bytes, kept coherent by the accesses made through it.
//
// Each access names a memory space and a mode (see Access). The variable tracks which copies
// hold the current contents and copies only when an access needs contents that the accessed
// side does not have:
//   host write -> device read      copies host to device once
//   device write -> host read      copies device to host once (waits for the device)
//   device read -> device read     copies nothing
//   host write -> device write     copies nothing (the device will overwrite everything)
// Resizing keeps the contents wherever they are current. New elements are zero bytes on both
// sides (for the trivial types variables hold, that is the value T{}).
// Each copy is allocated on its side's first access: a variable used only on the device never
// takes host memory, and a new variable's zeros are set on the device, not copied there.

#include <cstdint>
#include <string>

#include "unisph/core/config.hpp"
#include "unisph/memory/space.hpp"

namespace unisph {

class VariableBase {
 public:
  VariableBase(std::string name, std::size_t element_size, std::size_t element_alignment, Index count);
  virtual ~VariableBase();
  VariableBase(const VariableBase&) = delete;
  VariableBase& operator=(const VariableBase&) = delete;

  const std::string& name() const { return name_; }
  Index size() const { return count_; }
  std::size_t element_size() const { return element_size_; }
  std::size_t bytes() const { return count_ * element_size_; }

  // Makes the copy in `space` usable for `mode` and returns its address (nullptr when empty).
  void* prepare(MemorySpace space, Access mode);

  // A number that changes whenever the buffer in `space` is (re)allocated or the size changes:
  // kernels holding views compare it to know when to rebuild. Unique across all variables.
  std::uint64_t layout_stamp(MemorySpace space) const { return stamp_[static_cast<int>(space)]; }

  // Which copies hold the current contents (for diagnostics and tests).
  bool is_current(MemorySpace space) const { return current_[static_cast<int>(space)]; }
  bool device_allocated() const { return device_allocated_; }
  bool host_allocated() const { return host_allocated_; }
  // Number of host->device and device->host copies this variable has made.
  std::uint64_t copies_to_device() const { return copies_to_device_; }
  std::uint64_t copies_to_host() const { return copies_to_host_; }

  // "variable 'Position' (1000 elements of 24 bytes)" — used in error messages.
  std::string describe() const;

 protected:
  void resize_elements(Index count);

 private:
  void ensure_host_allocation();
  void ensure_device_allocation();
  void copy_host_to_device();
  void copy_device_to_host();

  std::string name_;
  std::size_t element_size_;
  std::size_t alignment_;
  Index count_ = 0;
  void* host_ = nullptr;
  void* device_ = nullptr;
  bool host_allocated_ = false;
  bool device_allocated_ = false;
  // Bytes allocated on each side: a resize within them keeps the allocation (a run on several
  // ranks resizes every particle variable at each step as particles migrate and ghosts change).
  std::size_t host_capacity_ = 0;
  std::size_t device_capacity_ = 0;
  bool current_[2] = {true, false};
  std::uint64_t stamp_[2] = {0, 0};
  std::uint64_t copies_to_device_ = 0;
  std::uint64_t copies_to_host_ = 0;
};

}  // namespace unisph
