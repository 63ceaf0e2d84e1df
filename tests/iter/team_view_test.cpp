// collective_for<TeamSize>: teams smaller than a CUDA block (several per block: 16 teams of 16,
// 8 of 32, 4 of 64, 2 of 128), and one team of 512 per block, sharing a view of a package's data
// points (iter::PackageDataPoints) with the team as the view's Collectivity. The test needs the
// team's sync(): on every trip each worker publishes its slot in memory the team shares, meets the
// team, reads the slot of a worker `shift` ranks further on (in another warp where the team has
// several), and meets the team again before the memory is written anew. Workers are held up by
// different times (on the GPU), so a sync() that did not wait for the whole team (or waited for
// the wrong threads) would read stale or future values. Every policy: on the host a team is made
// of std::threads sharing a std::barrier.
#include <cstdint>
#include <string>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/iter/collective_for.hpp"
#include "unisph/grid/package_traits.hpp"
#include "unisph/iter/view.hpp"

namespace {
using namespace unisph;
namespace direction = iter::direction;

// What worker r of group g publishes on a trip: its point's address, or -1 for a padding slot.
constexpr long long code(Index g, long long local) { return local < 0 ? -1 : (long long)g * 10000 + local; }

template <int D, Index Size>
struct ExchangeThroughTheTeam {
  static constexpr Index points = package_points<D>;
  static constexpr Index trips = (points + Size - 1) / Size;
  Index shift;
  unisph::View<long long> shared;  // Size per group: what the team's workers publish
  unisph::View<long long> read;    // trips * Size per group: what worker r read on trip t
  unisph::View<Index> made;        // Size per group: the trips each worker made
  template <class Team>
  UNISPH_HOST_DEVICE void operator()(const Team& team, Index g) const {
    using Points = iter::View<iter::PackageDataPoints<D>, direction::Forward, Team, iter::CompileTimeTuple<>>;
    const Points view(iter::PackageDataPoints<D>::of(std::uint32_t(g + iter::first_data_package)), {}, iter::NoChild{}, team);
    long long* mine = &shared[g * Size];
    const Index r = team.rank();
    Index t = 0;
    for (auto slot : view) {
#if UNISPH_DEVICE_CODE
      __nanosleep(unsigned((r * 7 + t * 3) % 11) * 200u);  // workers arrive at different times
#endif
      mine[r] = slot ? code(g, slot->local_point) : -1;
      team.sync();
      const long long other = mine[(r + shift) % Size];
      team.sync();  // nobody publishes the next trip's value before every worker has read this one
      if (t < trips) read[(g * trips + t) * Size + r] = other;
      ++t;
    }
    made[g * Size + r] = t;
  }
};

template <int D, Index Size, class P>
void check_exchange(P policy, Index groups, Index shift) {
  using Kernel = ExchangeThroughTheTeam<D, Size>;
  constexpr Index trips = Kernel::trips, points = Kernel::points;
  DiscreteVariable<long long> shared("shared", groups * Size), read("read", groups * trips * Size);
  DiscreteVariable<Index> made("made", groups * Size);
  iter::collective_for<Size>(policy, groups,
                             Kernel{shift, shared.read_write(policy), read.write(policy), made.write(policy)});
  fence(policy);
  std::vector<long long> expected(groups * trips * Size);
  for (Index g = 0; g < groups; ++g)
    for (Index t = 0; t < trips; ++t)
      for (Index r = 0; r < Size; ++r) {
        // Worker r's slot on trip t is point t * Size + r (offset r, jump Size), padding from 4^D on.
        const Index local = t * Size + (r + shift) % Size;
        expected[(g * trips + t) * Size + r] = code(g, local < points ? (long long)local : -1);
      }
  const std::string where = std::to_string(D) + "D points, teams of " + std::to_string(Size) + ", shift " +
                            std::to_string(shift) + ", " + std::to_string(groups) + " groups";
  EXPECT_EQ(read.to_vector(), expected) << where;
  EXPECT_EQ(made.to_vector(), std::vector<Index>(groups * Size, trips)) << where << ": every worker makes the same trips";
}

UNISPH_POLICY_TEST_SUITE(TeamViews);

TYPED_TEST(TeamViews, TeamsWithinAWarpMeetAtTheirSync) {
  // 16 teams of 16 per block; 2D packages: one trip; 3D packages: four trips.
  check_exchange<2, 16>(this->policy, 37, 5);
  check_exchange<3, 16>(this->policy, 37, 9);
  // 8 teams of 8, a team of a whole warp.
  check_exchange<3, 8>(this->policy, 21, 3);
  check_exchange<3, 32>(this->policy, 19, 17);
}

TYPED_TEST(TeamViews, TeamsOfSeveralWarpsMeetAtTheirNamedBarrier) {
  // 4 teams of 64 per block (data_point_for's teams in 3D), the partner in the other warp; 2 teams
  // of 128 (half of each team's slots padding); one team of 512 per block (__syncthreads).
  check_exchange<3, 64>(this->policy, 29, 33);
  check_exchange<3, 64>(this->policy, 3, 1);
  check_exchange<3, 128>(this->policy, 11, 70);
  if constexpr (TypeParam::space == MemorySpace::device) check_exchange<3, 512>(this->policy, 5, 300);
}

TYPED_TEST(TeamViews, NoGroupsLaunchNothing) {
  check_exchange<3, 64>(this->policy, 0, 1);
  check_exchange<2, 16>(this->policy, 0, 1);
}

}  // namespace
