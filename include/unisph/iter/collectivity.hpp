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
//   DeviceTeam<Size, TeamsPerBlock>
//               Size consecutive threads of a CUDA block of TeamsPerBlock such teams
//               (collective_for<Size> on par_device); size() is the compile-time Size, so a view's
//               trip arithmetic folds; sync() waits for this team only: __syncwarp(mask) for a
//               team within one warp, the named barrier `bar.sync 1 + team, Size` for a team of
//               whole warps, __syncthreads() for a team that is the whole block
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

// Team sizes collective_for<Size> can make on the GPU: a power of two up to a warp (the team lies
// within one warp), or whole warps up to a block of 1024 threads.
template <Index Size>
inline constexpr bool valid_device_team_size =
    Size >= 1 && Size <= 1024 && (Size <= 32 ? (Size & (Size - 1)) == 0 : Size % 32 == 0);

// Named barriers 1..15 are free for teams (barrier 0 is __syncthreads()).
inline constexpr Index max_named_barrier_teams = 15;

template <Index Size, Index TeamsPerBlock>
struct DeviceTeam {
  static_assert(valid_device_team_size<Size>,
                "iter::collectivity::DeviceTeam<Size, ...>: a team of threads is either a power of two up to 32 (it lies "
                "within one warp and meets at __syncwarp) or a multiple of 32 up to 1024 (whole warps, which meet at a "
                "named barrier); other sizes would split a warp between teams.");
  static_assert(TeamsPerBlock >= 1 && Size * TeamsPerBlock <= 1024,
                "iter::collectivity::DeviceTeam<Size, TeamsPerBlock>: the teams of a block are at most 1024 threads.");
  static_assert(Size <= 32 || TeamsPerBlock == 1 || TeamsPerBlock <= max_named_barrier_teams,
                "iter::collectivity::DeviceTeam<Size, TeamsPerBlock>: teams of whole warps meet at named barriers 1..15, "
                "so a block holds at most 15 of them.");

  // The worker's place in its team and the team's place in the block; valid only in device code
  // (on the host they read as worker 0 of team 0).
  UNISPH_HOST_DEVICE Index rank() const {
#if UNISPH_DEVICE_CODE
    return Index(threadIdx.x % unsigned(Size));
#else
    return 0;
#endif
  }
  UNISPH_HOST_DEVICE Index team() const {
#if UNISPH_DEVICE_CODE
    return Index(threadIdx.x / unsigned(Size));
#else
    return 0;
#endif
  }
  UNISPH_HOST_DEVICE static constexpr Index size() { return Size; }
  UNISPH_HOST_DEVICE static constexpr Index teams_per_block() { return TeamsPerBlock; }
  // Waits until every thread of this team has arrived (the other teams of the block go on), and
  // makes what they wrote before it visible to each other.
  UNISPH_HOST_DEVICE void sync() const {
#if UNISPH_DEVICE_CODE
    if constexpr (TeamsPerBlock == 1) {
      __syncthreads();
    } else if constexpr (Size == 32) {
      __syncwarp();
    } else if constexpr (Size < 32) {
      const unsigned first_lane = (threadIdx.x % 32u) / unsigned(Size) * unsigned(Size);
      __syncwarp(((1u << unsigned(Size)) - 1u) << first_lane);
    } else {
      asm volatile("bar.sync %0, %1;" ::"r"(1u + threadIdx.x / unsigned(Size)), "r"(unsigned(Size)) : "memory");
    }
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

static_assert(Collectivity<None> && Collectivity<HostTeam> && Collectivity<DeviceBlock> && Collectivity<DeviceTeam<64, 4>> &&
              Collectivity<DeviceTeam<16, 16>>);

}  // namespace unisph::iter::collectivity
