// iter::View against plain loops: forward and backward at each level, offsets, jumps larger
// than the count, element counts, empty supercells, empty frames, last frames exactly full;
// three levels deep; a team of 256 sharing a walk with a barrier on every trip; the view as a
// C++20 range; the supercell container's links.
#include <algorithm>
#include <numeric>
#include <ranges>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/atomic.hpp"
#include "unisph/iter/iter.hpp"

namespace {
using namespace unisph;
using iter::all;
using iter::RuntimeTuple;
namespace direction = iter::direction;
namespace collectivity = iter::collectivity;

struct Tagged {
  int id;     // unique over the container
  int value;  // what the team test sums
};

// ---- walks against plain loops ----------------------------------------------------------------

constexpr Index small_frame = 4;
using SmallFrame = iter::Frame<Tagged, small_frame>;
using SmallContainer = iter::SupercellContainer<Tagged, small_frame>;
constexpr Index max_visits = 64;

// Particle counts of the supercells walked; -1 is a supercell of one frame with no particle.
const std::vector<int> supercell_sizes = {0, -1, 12, 9, 1, 26};

void fill_small_container(SmallContainer& container) {
  container.add_supercells(supercell_sizes.size());
  int id = 0;
  for (Index c = 0; c < supercell_sizes.size(); ++c) {
    if (supercell_sizes[c] < 0) {
      container.append_empty_frame(c);
      continue;
    }
    std::vector<Tagged> particles;
    for (int p = 0; p < supercell_sizes[c]; ++p, ++id) particles.push_back({id, 3 * id + 1});
    container.append(c, particles);
  }
}

template <class FrameDirection, class SlotDirection>
struct RecordWalk {
  iter::Supercells<const SmallFrame> cells;
  RuntimeTuple frames, slots;
  unisph::View<int> ids;        // max_visits per supercell, in visiting order
  unisph::View<Index> valid;    // per supercell
  unisph::View<Index> trips;    // per supercell, valid or not
  UNISPH_HOST_DEVICE void operator()(Index c) const {
    using Slots = iter::View<const SmallFrame, SlotDirection>;
    iter::View<iter::Supercell<const SmallFrame>, FrameDirection, collectivity::None, RuntimeTuple, Slots> view(
        cells[c], frames, Slots(nullptr, slots));
    Index n = 0, t = 0;
    for (auto slot : view) {  // a range-for works as well as the slides' explicit iterator loop
      ++t;
      if (slot && n < max_visits) ids[c * max_visits + n++] = slot->id;
    }
    valid[c] = n;
    trips[c] = t;
    // for_each must visit the same slots in the same order; a difference sets valid[c] to ~0.
    Index k = 0, u = 0;
    bool same = true;
    view.for_each(Compare{ids, c * max_visits, n, k, u, same});
    if (!same || k != n || u != t) valid[c] = ~Index(0);
  }
  struct Compare {
    unisph::View<int> ids;
    Index base, n;
    Index& k;
    Index& u;
    bool& same;
    UNISPH_HOST_DEVICE void operator()(iter::SlotRef<const Tagged> slot) const {
      ++u;
      if (slot) {
        if (k >= n || ids[base + k] != slot->id) same = false;
        ++k;
      }
    }
  };
};

// What the plain loop visits: the frames of the list in walking order, the positions
// offset, offset + jump, ... below the count, then the same for the slots of each frame.
std::vector<int> plain_walk(const iter::Supercells<SmallFrame>& host, Index c, bool frames_forward, RuntimeTuple frames,
                            bool slots_forward, RuntimeTuple slots) {
  std::vector<Index> list;
  for (Index f = host[c].header.first_frame; f != iter::no_frame; f = host.frames[f].next) list.push_back(f);
  if (!frames_forward) std::reverse(list.begin(), list.end());
  const Index frame_count = std::min<Index>(frames.count, list.size());
  std::vector<int> ids;
  for (Index p = frames.offset; p < frame_count; p += frames.jump) {
    const Index frame = list[p];
    for (Index q = slots.offset; q < small_frame; q += slots.jump) {
      const Index slot = slots_forward ? q : small_frame - 1 - q;
      if (slot < host[c].fill_of(frame)) ids.push_back(host.frames[frame].slots[slot].id);
    }
  }
  return ids;
}

// The number of trips by the rule of iter/view.hpp: ceil(C / j) - floor(o / j) at each level.
Index rule_trips(Index count, RuntimeTuple r) {
  const Index rounds = (count + r.jump - 1) / r.jump, skipped = r.offset / r.jump;
  return skipped < rounds ? rounds - skipped : 0;
}

template <class FrameDirection, class SlotDirection, class Policy>
void check_walks(Policy policy, SmallContainer& container) {
  const Index cells = container.supercell_count();
  DiscreteVariable<int> ids("ids", cells * max_visits);
  DiscreteVariable<Index> valid("valid", cells), trips("trips", cells);
  for (Index frame_offset : {0, 1, 3})
    for (Index frame_count : {all, Index(2), Index(0)})
      for (Index frame_jump : {1, 2, 7})
        for (Index slot_offset : {0, 1, 3})
          for (Index slot_jump : {1, 2, 7}) {
            const RuntimeTuple frames{frame_offset, frame_count, frame_jump};
            const RuntimeTuple slots{slot_offset, all, slot_jump};
            particle_for(policy, cells,
                         RecordWalk<FrameDirection, SlotDirection>{container.read(policy), frames, slots,
                                                                   ids.write(policy), valid.write(policy),
                                                                   trips.write(policy)});
            const std::vector<int> found = ids.to_vector();
            const std::vector<Index> found_valid = valid.to_vector(), found_trips = trips.to_vector();
            const iter::Supercells<SmallFrame> host = container.read_write(MemorySpace::host);
            for (Index c = 0; c < cells; ++c) {
              const std::vector<int> expected =
                  plain_walk(host, c, FrameDirection::is_forward, frames, SlotDirection::is_forward, slots);
              ASSERT_NE(found_valid[c], ~Index(0)) << "for_each differs from the iterator loop in supercell " << c;
              const std::vector<int> got(found.begin() + c * max_visits, found.begin() + c * max_visits + found_valid[c]);
              const Index frames_used = std::min<Index>(frame_count, host[c].header.frame_count);
              const std::string where = "supercell " + std::to_string(c) + " frames (" + std::to_string(frame_offset) +
                                        ", " + (frame_count == all ? "all" : std::to_string(frame_count)) + ", " +
                                        std::to_string(frame_jump) + ") slots (" + std::to_string(slot_offset) + ", " +
                                        std::to_string(slot_jump) + ")";
              ASSERT_EQ(got, expected) << where;
              EXPECT_EQ(found_trips[c], rule_trips(frames_used, frames) * rule_trips(small_frame, slots)) << where;
            }
          }
}

UNISPH_POLICY_TEST_SUITE(ViewWalks);

TYPED_TEST(ViewWalks, ForwardFramesForwardSlotsMatchPlainLoops) {
  SmallContainer container("walks");
  fill_small_container(container);
  check_walks<direction::Forward, direction::Forward>(this->policy, container);
}
TYPED_TEST(ViewWalks, BackwardFramesForwardSlotsMatchPlainLoops) {
  SmallContainer container("walks");
  fill_small_container(container);
  check_walks<direction::Backward, direction::Forward>(this->policy, container);
}
TYPED_TEST(ViewWalks, ForwardFramesBackwardSlotsMatchPlainLoops) {
  SmallContainer container("walks");
  fill_small_container(container);
  check_walks<direction::Forward, direction::Backward>(this->policy, container);
}
TYPED_TEST(ViewWalks, BackwardFramesBackwardSlotsMatchPlainLoops) {
  SmallContainer container("walks");
  fill_small_container(container);
  check_walks<direction::Backward, direction::Backward>(this->policy, container);
}

// Three levels: every supercell (backward, every second), every frame, every slot.
struct SumThreeLevels {
  iter::Supercells<const SmallFrame> cells;
  unisph::View<long long> sum_and_count;
  UNISPH_HOST_DEVICE void operator()(Index) const {
    using Slots = iter::View<const SmallFrame>;
    using Frames = iter::View<iter::Supercell<const SmallFrame>, direction::Forward, collectivity::None,
                              iter::CompileTimeTuple<>, Slots>;
    iter::View<iter::Supercells<const SmallFrame>, direction::Backward, collectivity::None, RuntimeTuple, Frames> view(
        cells, RuntimeTuple{0, all, 2}, Frames(nullptr, {}, Slots(nullptr)));
    long long sum = 0, count = 0;
    for (auto it = view.begin(); it != view.end(); ++it)
      if (*it) sum += (*it)->value, ++count;
    sum_and_count[0] = sum;
    sum_and_count[1] = count;
  }
};

TYPED_TEST(ViewWalks, ThreeLevelsMatchAPlainLoop) {
  SmallContainer container("walks");
  fill_small_container(container);
  DiscreteVariable<long long> result("result", 2);
  particle_for(this->policy, 1, SumThreeLevels{container.read(this->policy), result.write(this->policy)});
  const iter::Supercells<SmallFrame> host = container.read_write(MemorySpace::host);
  long long sum = 0, count = 0;
  for (Index c = host.size() - 1; c < host.size(); c -= 2)  // the last, the third from last, ...
    for (Index f = host[c].header.first_frame; f != iter::no_frame; f = host.frames[f].next)
      for (Index s = 0; s < host[c].fill_of(f); ++s) sum += host.frames[f].slots[s].value, ++count;
  EXPECT_GT(count, 0);
  EXPECT_EQ(result.to_vector(), (std::vector<long long>{sum, count}));
}

// A view inside particle_reduce: one supercell per item, its particles summed through the view.
struct SupercellValueSum {
  iter::Supercells<const SmallFrame> cells;
  UNISPH_HOST_DEVICE double operator()(Index c) const {
    using Slots = iter::View<const SmallFrame>;
    const iter::View<iter::Supercell<const SmallFrame>, direction::Forward, collectivity::None, RuntimeTuple, Slots> view(
        cells[c], RuntimeTuple{}, Slots(nullptr));
    double sum = 0;
    for (auto slot : view)
      if (slot) sum += slot->value;
    return sum;
  }
};

TYPED_TEST(ViewWalks, ParticleReduceOverSupercellsMatchesTheHostSum) {
  SmallContainer container("reduce", 8192);
  double expected = 0;
  for (Index c = 0; c < container.supercell_count(); ++c) {
    std::vector<Tagged> particles;
    for (Index p = 0; p < c % 11; ++p) particles.push_back({int(p), int(c % 1000 + p)}), expected += double(c % 1000 + p);
    container.append(c, particles);
  }
  EXPECT_EQ(particle_reduce(this->policy, container.supercell_count(), Sum<double>{},
                            SupercellValueSum{container.read(this->policy)}),
            expected);
}

// ---- a team of 256 shares one walk per supercell ----------------------------------------------
//
// Frames of 300 slots: a team of 256 makes ceil(300 / 256) = 2 trips per frame, and threads
// 44..255 meet padding positions (300..511) on the second trip. On every trip each thread posts
// its particle's value in the team's buffer, the team meets at the barrier, the mover adds the
// buffer up, and the team meets again before the buffer is reused. Were the trip counts unequal,
// the barrier would hang (host) or be undefined (__syncthreads on the device).

constexpr Index team_size = 256;
constexpr Index big_frame = 300;
using BigFrame = iter::Frame<Tagged, big_frame>;
using BigContainer = iter::SupercellContainer<Tagged, big_frame>;

struct TeamSum {
  iter::Supercells<const BigFrame> cells;
  unisph::View<long long> buffer;  // team_size per supercell
  unisph::View<long long> sums;    // per supercell, written by the mover
  unisph::View<int> visits;        // per particle id
  unisph::View<int> trips;         // per supercell and thread
  template <class Team>
  UNISPH_HOST_DEVICE void operator()(const Team& team, Index c) const {
    using Slots = iter::View<const BigFrame, direction::Forward, Team>;
    iter::View<iter::Supercell<const BigFrame>, direction::Forward, collectivity::None, RuntimeTuple, Slots> view(
        cells[c], RuntimeTuple{}, Slots(nullptr, RuntimeTuple{}, iter::NoChild{}, team));
    long long* shared = &buffer[c * team_size];
    for (auto it = view.begin(); it != view.end(); ++it) {
      const auto slot = *it;
      shared[team.rank()] = slot ? slot->value : 0;
      if (slot) atomic_add(&visits[slot->id], 1);
      atomic_add(&trips[c * team_size + team.rank()], 1);
      team.sync();
      if (team.is_mover()) {
        long long total = 0;
        for (Index r = 0; r < team_size; ++r) total += shared[r];
        sums[c] += total;
      }
      team.sync();
    }
  }
};

UNISPH_POLICY_TEST_SUITE(TeamWalks);

TYPED_TEST(TeamWalks, TeamOf256VisitsEveryValidParticleOnceWithABarrierOnEveryTrip) {
  const std::vector<int> sizes = {1000, 0, 300, 1, 601};
  BigContainer container("team", sizes.size());
  std::vector<long long> expected_sums;
  int id = 0;
  for (Index c = 0; c < sizes.size(); ++c) {
    std::vector<Tagged> particles;
    long long sum = 0;
    for (int p = 0; p < sizes[c]; ++p, ++id) particles.push_back({id, 7 * id + 3}), sum += 7 * id + 3;
    container.append(c, particles);
    expected_sums.push_back(sum);
  }
  DiscreteVariable<long long> buffer("buffer", sizes.size() * team_size), sums("sums", sizes.size());
  DiscreteVariable<int> visits("visits", Index(id)), trips("trips", sizes.size() * team_size);
  iter::collective_for(this->policy, sizes.size(), team_size,
                       TeamSum{container.read(this->policy), buffer.write(this->policy), sums.read_write(this->policy),
                               visits.read_write(this->policy), trips.read_write(this->policy)});
  EXPECT_EQ(sums.to_vector(), expected_sums);
  const std::vector<int> seen = visits.to_vector();
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), id) << "every valid particle exactly once";
  const std::vector<int> made = trips.to_vector();
  for (Index c = 0; c < sizes.size(); ++c) {
    const int frames = (sizes[c] + int(big_frame) - 1) / int(big_frame);
    for (Index r = 0; r < team_size; ++r)
      ASSERT_EQ(made[c * team_size + r], frames * 2) << "supercell " << c << ", thread " << r;
  }
}

// ---- host: ranges, compile-time tuples, the container, collective_for's errors ---------------

using HostSlots = iter::View<SmallFrame>;
using HostParticles = iter::View<iter::Supercell<SmallFrame>, direction::Forward, collectivity::None, RuntimeTuple, HostSlots>;
static_assert(std::ranges::forward_range<HostSlots> && std::ranges::view<HostSlots>);
static_assert(std::ranges::forward_range<HostParticles> && std::ranges::view<HostParticles>);
static_assert(std::is_trivially_copyable_v<HostParticles> && std::is_trivially_copyable_v<HostParticles::iterator>);
static_assert(!iter::HasContainerTraits<std::vector<int>>, "a container without traits cannot be viewed");

TEST(HostViewRange, ComposesWithStdViews) {
  SmallContainer container("walks");
  fill_small_container(container);
  const iter::Supercells<SmallFrame> host = container.read_write(MemorySpace::host);
  const HostParticles particles(host[5], RuntimeTuple{}, HostSlots(nullptr));
  std::vector<int> expected;
  for (Index f = host[5].header.first_frame; f != iter::no_frame; f = host.frames[f].next)
    for (Index s = 0; s < host[5].fill_of(f); ++s) expected.push_back(host.frames[f].slots[s].value);
  EXPECT_EQ(std::ranges::distance(particles), 7 * 4);  // 7 frames of 4 slots, 2 of them free
  EXPECT_EQ(std::ranges::count_if(particles, [](auto slot) { return !slot; }), 2);
#if defined(__clang__) && __clang_major__ < 16
  // Clang before 16 cannot instantiate libstdc++ 12's filter_view (it does not see its
  // constrained begin()); the GCC build, the default preset, checks the composition.
#else
  auto values = particles | std::views::filter([](auto slot) { return bool(slot); }) |
                std::views::transform([](auto slot) { return slot->value; });
  std::vector<int> got;
  for (int v : values) got.push_back(v);
  EXPECT_EQ(got, expected);
  std::vector<int> first_three;
  for (int v : values | std::views::take(3)) first_three.push_back(v);
  EXPECT_EQ(first_three, std::vector<int>(expected.begin(), expected.begin() + 3));
#endif
  // Writing through the slots changes the container.
  for (auto slot : particles)
    if (slot) slot->value = -slot->value;
  EXPECT_EQ(host.frames[host[5].header.first_frame].slots[0].value, -expected[0]);
}

TEST(HostViewRange, CompileTimeTupleWalksLikeTheRuntimeTuple) {
  SmallContainer container("walks");
  fill_small_container(container);
  const iter::Supercells<SmallFrame> host = container.read_write(MemorySpace::host);
  using Fixed = iter::View<iter::Supercell<SmallFrame>, direction::Backward, collectivity::None,
                           iter::CompileTimeTuple<1, all, 2>, iter::View<SmallFrame, direction::Forward, collectivity::None,
                                                                          iter::CompileTimeTuple<1, all, 2>>>;
  using Dynamic = iter::View<iter::Supercell<SmallFrame>, direction::Backward, collectivity::None, RuntimeTuple,
                             iter::View<SmallFrame>>;
  static_assert(sizeof(Fixed) < sizeof(Dynamic), "compile-time values take no room");
  std::vector<int> fixed, dynamic;
  for (auto slot : Fixed(host[5]))
    if (slot) fixed.push_back(slot->id);
  for (auto slot : Dynamic(host[5], RuntimeTuple{1, all, 2}, iter::View<SmallFrame>(nullptr, RuntimeTuple{1, all, 2})))
    if (slot) dynamic.push_back(slot->id);
  EXPECT_FALSE(fixed.empty());
  EXPECT_EQ(fixed, dynamic);
}

TEST(HostViewRange, IteratorsOfOneViewCompareByPosition) {
  SmallContainer container("walks");
  fill_small_container(container);
  const HostParticles particles(container.read_write(MemorySpace::host)[3], RuntimeTuple{}, HostSlots(nullptr));
  auto a = particles.begin(), b = particles.begin();
  EXPECT_TRUE(a == b);
  ++a;
  EXPECT_FALSE(a == b);
  b++;
  EXPECT_TRUE(a == b);
  EXPECT_EQ(std::ranges::next(particles.begin(), 12), particles.end());  // 3 frames of 4 slots
}

TEST(HostSupercellContainer, ChainsFramesBothWaysAndKnowsTheLastFill) {
  SmallContainer container("chain", 2);
  for (int p = 0; p < 9; ++p) {
    container.push_back(0, Tagged{p, 0});
    container.push_back(1, Tagged{100 + p, 0});  // interleaved: the two lists share the pool
  }
  const iter::Supercells<SmallFrame> host = container.read_write(MemorySpace::host);
  for (Index c = 0; c < 2; ++c) {
    const iter::Supercell<SmallFrame> cell = host[c];
    EXPECT_EQ(cell.header.frame_count, 3u);
    EXPECT_EQ(cell.header.particles_in_last_frame, 1u);
    EXPECT_EQ(cell.particle_count(), 9u);
    std::vector<Index> forward, backward;
    for (Index f = cell.header.first_frame; f != iter::no_frame; f = host.frames[f].next) forward.push_back(f);
    for (Index f = cell.header.last_frame; f != iter::no_frame; f = host.frames[f].previous) backward.push_back(f);
    std::reverse(backward.begin(), backward.end());
    EXPECT_EQ(forward, backward);
    EXPECT_EQ(host.frames[forward[1]].slots[0].id, int(100 * c) + 4);
  }
  EXPECT_EQ(container.frame_count(), 6u);
  EXPECT_THROW(container.push_back(2, Tagged{}), Error);
  EXPECT_THROW(container.append_empty_frame(2), Error);
}

struct ThrowOnRankTwo {
  template <class Team>
  void operator()(const Team& team, Index) const {
    team.sync();
    if (team.rank() == 2) throw std::runtime_error("rank 2 gives up");
    team.sync();
  }
};

// Counts, per group, how many workers ran it and which team sizes they saw.
struct CountWorkers {
  unisph::View<int> workers;
  template <class Team>
  void operator()(const Team& team, Index g) const {
    atomic_add(&workers[g], 1);
    team.sync();
    if (team.is_mover()) atomic_add(&workers[g], 1000 * int(team.size()));
  }
};

TEST(HostCollectiveFor, EveryGroupRunsOnceWithItsWholeTeamOnSeqAndPar) {
  // par runs cores / team_size teams side by side (more than one for a team of 1 on 2+ cores).
  for (Index team_size : {1, 2, 3}) {
    DiscreteVariable<int> seq_workers("seq", 17), par_workers("par", 17);
    iter::collective_for(seq, 17, team_size, CountWorkers{seq_workers.read_write(MemorySpace::host)});
    iter::collective_for(par, 17, team_size, CountWorkers{par_workers.read_write(MemorySpace::host)});
    const std::vector<int> expected(17, int(team_size) + 1000 * int(team_size));
    EXPECT_EQ(seq_workers.to_vector(), expected) << "team of " << team_size;
    EXPECT_EQ(par_workers.to_vector(), expected) << "team of " << team_size;
  }
}

TEST(HostCollectiveFor, AnExceptionInOneThreadReachesTheCallerWithoutHangingTheTeam) {
  EXPECT_THROW(iter::collective_for(seq, 3, 4, ThrowOnRankTwo{}), std::runtime_error);
  EXPECT_THROW(iter::collective_for(seq, 1, 0, ThrowOnRankTwo{}), Error);
}

}  // namespace
