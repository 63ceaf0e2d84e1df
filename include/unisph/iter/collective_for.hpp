#pragma once
// collective_for(policy, groups, team_size, kernel): kernel(team, g) for every g in
// [0, groups), where the `team_size` workers of a team run the same g together and may meet
// at team.sync() inside it (typically: all threads of a team share the walk of supercell g
// through a view with the team as its Collectivity).
//
//   par_device   one CUDA block of team_size threads per group (team: collectivity::DeviceBlock,
//                sync() = __syncthreads()); asynchronous on unisph's stream like particle_for
//   seq          one team of team_size std::threads with a std::barrier, groups one after another
//   par          as many such teams as the machine has cores for, groups shared round robin
//
// The host teams are std::threads, never oneTBB tasks: a barrier between tasks can wait forever,
// because oneTBB does not promise that tasks run at the same time.
//
// collective_for<TeamSize>(policy, groups, kernel): the same with a team size known at compile
// time, for small teams (the 4^D data points of a package: data_point_for):
//
//   par_device   several teams per CUDA block (TeamsPerBlock = 256 / TeamSize, one team per block
//                from 256 threads on): team t of block b runs groups b * TeamsPerBlock + t, then a
//                grid's worth further; team: collectivity::DeviceTeam<TeamSize, TeamsPerBlock>, whose
//                size() is the constant TeamSize (a view's trip arithmetic folds) and whose sync()
//                waits for the team alone (__syncwarp(mask) within a warp, a named barrier for whole
//                warps). TeamSize: a power of two up to 32 or a multiple of 32 up to 1024.
//   seq, par     as collective_for(policy, groups, TeamSize, kernel): teams of std::threads
//
// The kernel is a trivially copyable function object with a template call operator, since the
// team's type differs between host and device:
//   struct K { template <class Team> UNISPH_HOST_DEVICE void operator()(const Team& team, Index g) const; };
// Every worker must reach the same team.sync() calls (a view shared through the team's
// collectivity guarantees equal trip counts).

#include <algorithm>
#include <barrier>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "unisph/core/error.hpp"
#include "unisph/exec/policy.hpp"
#include "unisph/iter/collectivity.hpp"

#if UNISPH_HAS_CUDA && defined(__CUDACC__)
#include <cuda_runtime.h>

#include "unisph/exec/backend/cuda/runtime.hpp"
#else
#include "unisph/exec/backend/backend.hpp"
#endif

namespace unisph::iter {

namespace detail {

template <class K>
constexpr void check_collective_kernel() {
  static_assert(std::is_trivially_copyable_v<K>,
                "a collective_for kernel is copied byte for byte into every launch (to the GPU as well), so it must be "
                "trivially copyable: hold Views and plain values, not std::vector, references or virtual functions.");
  static_assert(std::is_invocable_v<const K&, const collectivity::HostTeam&, Index>,
                "a collective_for kernel is called as kernel(team, group) with the team as a template parameter: "
                "template <class Team> UNISPH_HOST_DEVICE void operator()(const Team& team, Index group) const.");
}

// `teams` teams of `team_size` std::threads; team t runs groups t, t + teams, ...
template <class K>
void run_host_teams(Index groups, Index team_size, Index teams, const K& kernel) {
  std::vector<std::unique_ptr<std::barrier<>>> barriers;  // a barrier cannot move
  for (Index t = 0; t < teams; ++t) barriers.push_back(std::make_unique<std::barrier<>>(static_cast<std::ptrdiff_t>(team_size)));
  std::exception_ptr failure;
  std::mutex failure_mutex;
  std::vector<std::thread> threads;
  threads.reserve(teams * team_size);
  for (Index t = 0; t < teams; ++t)
    for (Index r = 0; r < team_size; ++r)
      threads.emplace_back([&, t, r] {
        const collectivity::HostTeam team(barriers[t].get(), r, team_size);
        const K local = kernel;  // a private copy, as on the device
        try {
          for (Index g = t; g < groups; g += teams) local(team, g);
        } catch (...) {
          // Leave the barrier for good, so that the other threads of the team do not wait forever.
          barriers[t]->arrive_and_drop();
          const std::lock_guard lock(failure_mutex);
          if (!failure) failure = std::current_exception();
        }
      });
  for (std::thread& thread : threads) thread.join();
  if (failure) std::rethrow_exception(failure);
}

#if UNISPH_HAS_CUDA && defined(__CUDACC__)
template <class K>
__global__ void collective_kernel(Index groups, K kernel) {
  // The loop bound is the same for every thread of the block, so every thread reaches every sync.
  for (Index g = blockIdx.x; g < groups; g += gridDim.x) kernel(collectivity::DeviceBlock{}, g);
}

// Teams of TeamSize consecutive threads, TeamsPerBlock of them per block. The loop bound is the
// same for every thread of a team (not of the block: teams meet at their own barriers).
template <Index TeamSize, Index TeamsPerBlock, class K>
__global__ void __launch_bounds__(TeamSize * TeamsPerBlock) team_kernel(Index groups, K kernel) {
  const collectivity::DeviceTeam<TeamSize, TeamsPerBlock> team;
  const Index stride = Index(gridDim.x) * TeamsPerBlock;
  for (Index g = Index(blockIdx.x) * TeamsPerBlock + Index(threadIdx.x / unsigned(TeamSize)); g < groups; g += stride)
    kernel(team, g);
}
#endif

// Teams per CUDA block of collective_for<TeamSize>: blocks of 256 threads where teams are smaller.
template <Index TeamSize>
inline constexpr Index device_teams_per_block = TeamSize >= 256 ? 1 : 256 / TeamSize;

// A device launch in a translation unit that cannot make one: a CUDA build compiled this file
// with the host compiler (a build error), or the build has no CUDA (a run-time error).
template <class K>
void device_launch_outside_nvcc() {
#if UNISPH_HAS_CUDA
  static_assert(backend::dependent_false_v<K>,
                "collective_for(par_device, ...) launches a GPU kernel, so this source file must be compiled by nvcc: "
                "list it in unisph_kernel_sources() in CMake (or give it LANGUAGE CUDA).");
#else
  require_policy(PolicyKind::device);
#endif
}

}  // namespace detail

inline constexpr Index max_device_team_size = 1024;

template <ExecutionPolicy P, class K>
void collective_for(P, Index groups, Index team_size, const K& kernel) {
  detail::check_collective_kernel<K>();
  if (team_size == 0) throw Error("collective_for: a team needs at least one worker (team_size is 0)");
  if constexpr (P::space == MemorySpace::host) {
    if (groups == 0) return;
    Index teams = 1;
    if constexpr (std::is_same_v<P, ParallelPolicy>) {
      const Index cores = std::max<Index>(1, std::thread::hardware_concurrency());
      teams = std::clamp<Index>(cores / team_size, 1, groups);
    }
    detail::run_host_teams(groups, team_size, teams, kernel);
  } else {
#if UNISPH_HAS_CUDA && defined(__CUDACC__)
    cuda::require_device();
    if (team_size > max_device_team_size)
      throw Error("collective_for(par_device): a team is one CUDA block, at most " +
                  std::to_string(max_device_team_size) + " threads, not " + std::to_string(team_size));
    if (groups == 0) return;
    const Index blocks = std::min<Index>(groups, 2147483647);
    detail::collective_kernel<<<static_cast<unsigned>(blocks), static_cast<unsigned>(team_size), 0,
                                static_cast<cudaStream_t>(cuda::stream_handle())>>>(groups, kernel);
    cuda::check_launch("collective_for", groups);
#else
    detail::device_launch_outside_nvcc<K>();
#endif
  }
}

template <Index TeamSize, ExecutionPolicy P, class K>
void collective_for(P policy, Index groups, const K& kernel) {
  static_assert(collectivity::valid_device_team_size<TeamSize>,
                "collective_for<TeamSize>: a team is a power of two up to 32 threads (within one warp) or a multiple of "
                "32 up to 1024 (whole warps of one block); for other sizes use collective_for(policy, groups, "
                "team_size, kernel), one block per team.");
  if constexpr (P::space == MemorySpace::host) {
    collective_for(policy, groups, TeamSize, kernel);
  } else {
    (void)policy;
    detail::check_collective_kernel<K>();
#if UNISPH_HAS_CUDA && defined(__CUDACC__)
    cuda::require_device();
    if (groups == 0) return;
    constexpr Index teams = detail::device_teams_per_block<TeamSize>;
    const Index blocks = std::min<Index>((groups + teams - 1) / teams, 2147483647);
    detail::team_kernel<TeamSize, teams><<<static_cast<unsigned>(blocks), static_cast<unsigned>(TeamSize * teams), 0,
                                           static_cast<cudaStream_t>(cuda::stream_handle())>>>(groups, kernel);
    cuda::check_launch("collective_for<TeamSize>", groups);
#else
    detail::device_launch_outside_nvcc<K>();
#endif
  }
}

}  // namespace unisph::iter
