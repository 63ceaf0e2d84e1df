#pragma once
// Collectivity: who shares a traversal. The seed's interface is a class with sync() and
// isMover(); here sync(), is_mover(), plus rank() and size(), which a view uses to split its
// level among the workers: worker r starts r jumps further and every worker jumps size times
// as far. Every worker then makes the same number of trips (see view.hpp), so a sync() inside
// the loop body is reached by all of them equally often.
//
//   None        one worker: nothing to share (sync does nothing)
//   HostTeam    one of `size` std::threads sharing a std::barrier (collective_for on seq / par)
//   DeviceBlock the threads of one CUDA block; sync() is __syncthreads() (collective_for on par_device)
//
// A host team is made of std::threads, never of oneTBB tasks: oneTBB does not promise that
// tasks run at the same time, so a barrier between them can wait forever.

#include <barrier>
#include <type_traits>

#include "unisph/core/config.hpp"

namespace unisph::iter::collectivity {

struct None {
  UNISPH_HOST_DEVICE static constexpr Index rank() { return 0; }
  UNISPH_HOST_DEVICE static constexpr Index size() { return 1; }
  UNISPH_HOST_DEVICE static constexpr void sync() {}
  UNISPH_HOST_DEVICE static constexpr bool is_mover() { return true; }
};

class HostTeam {
 public:
  HostTeam() = default;
  HostTeam(std::barrier<>* barrier, Index rank, Index size) : barrier_(barrier), rank_(rank), size_(size) {}

  UNISPH_HOST_DEVICE Index rank() const { return rank_; }
  UNISPH_HOST_DEVICE Index size() const { return size_; }
  // Waits until every thread of the team has arrived. Host only (a team is made of std::threads).
  UNISPH_HOST_DEVICE void sync() const {
#if !UNISPH_DEVICE_CODE
    barrier_->arrive_and_wait();
#endif
  }
  // The thread that does what the team needs done once (the seed's isMover).
  UNISPH_HOST_DEVICE bool is_mover() const { return rank_ == 0; }

 private:
  std::barrier<>* barrier_ = nullptr;
  Index rank_ = 0;
  Index size_ = 1;
};

// The calling CUDA block; valid only in device code (on the host it reads as one worker).
struct DeviceBlock {
  UNISPH_HOST_DEVICE Index rank() const {
#if UNISPH_DEVICE_CODE
    return threadIdx.x;
#else
    return 0;
#endif
  }
  UNISPH_HOST_DEVICE Index size() const {
#if UNISPH_DEVICE_CODE
    return blockDim.x;
#else
    return 1;
#endif
  }
  UNISPH_HOST_DEVICE void sync() const {
#if UNISPH_DEVICE_CODE
    __syncthreads();
#endif
  }
  UNISPH_HOST_DEVICE bool is_mover() const { return rank() == 0; }
};

template <class C>
concept Collectivity = std::is_trivially_copyable_v<C> && requires(const C& c) {
  { c.rank() } -> std::convertible_to<Index>;
  { c.size() } -> std::convertible_to<Index>;
  c.sync();
  { c.is_mover() } -> std::convertible_to<bool>;
};

static_assert(Collectivity<None> && Collectivity<HostTeam> && Collectivity<DeviceBlock>);

}  // namespace unisph::iter::collectivity
