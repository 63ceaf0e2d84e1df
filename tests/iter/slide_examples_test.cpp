// The examples of the "Parallel Particle Iterators" slides (seed 002), with the slides' data and
// printed results, each run inside a kernel on every policy (seq, par, gpu). The slides print
// containers as [(a, b), ...] with the free slots of a last frame as (-1, -1); the tests print
// the same way and compare the text.
//
// Where the slides contradict themselves the tests decide, and say so:
//  - RuntimeTuple's argument order is (offset, element count, jump) (see iter/runtime.hpp).
//  - "Jedes zweite Frame" declares Direction::Backward but prints the frames first to last;
//    with 5 frames, offset 0 and jump 2 both directions visit frames 0, 2 and 4, so the test
//    checks the printed order with Forward and the reverse order with Backward.
//  - "Particle jedes zweiten Frames": the same (Backward declared, forward order printed). The
//    frame view's element count (2 there, nbElemsLastFrame in the five-thread example) is
//    ignored, as the printed results require: a frame's slot count is a compile-time trait
//    (needs_runtime_size is false), and its free slots are invalid.
//  - "Particle-Particle Interaktionen": the code has no braces, so as written the second loop
//    would run after the first with `it` at its end; the indentation says it is nested, and the
//    test nests it: every particle of the first supercell gets the sum of data[1] over the
//    second (51 + 53 + ... + 87 = 19 * 69 = 1311).
#include <algorithm>
#include <sstream>
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

struct Particle {
  int data[2];
};
constexpr Index slots_per_frame = 5;
using Frame = iter::Frame<Particle, slots_per_frame>;
using Container = iter::SupercellContainer<Particle, slots_per_frame>;
using Supercells = iter::Supercells<Frame>;

template <class Direction = direction::Forward>
using ParticlesInFrame = iter::View<Frame, Direction, collectivity::None, RuntimeTuple>;
template <class Direction>
using FramesOfSupercell = iter::View<iter::Supercell<Frame>, Direction, collectivity::None, RuntimeTuple>;
template <class Direction, class Child = ParticlesInFrame<>>
using ParticlesOfSupercell = iter::View<iter::Supercell<Frame>, Direction, collectivity::None, RuntimeTuple, Child>;

// ---- printing as the slides do -------------------------------------------------------------

std::string print(const Particle& p) {
  std::ostringstream text;
  text << '(' << p.data[0] << ", " << p.data[1] << ')';
  return text.str();
}
std::string print(const Frame& frame, Index fill) {
  std::string text = "[";
  for (Index s = 0; s < slots_per_frame; ++s) {
    if (s > 0) text += ", ";
    text += s < fill ? print(frame.slots[s]) : "(-1, -1)";
  }
  return text + "]";
}
// One line per frame, first to last.
std::string print(Container& container, Index supercell) {
  const Supercells host = container.read_write(MemorySpace::host);
  const iter::Supercell<Frame> cell = host[supercell];
  std::string text;
  for (Index f = cell.header.first_frame; f != iter::no_frame; f = host.frames[f].next)
    text += print(host.frames[f], cell.fill_of(f)) + "\n";
  return text;
}

// Appends `particles` particles to a supercell; slot s of its frame f holds (a, a + 1) with
// a = first + value_step_per_frame * f + 2 s, the pattern of the slides' supercells.
void fill_supercell(Container& container, Index supercell, int particles, int first, int value_step_per_frame) {
  std::vector<Particle> values;
  for (int p = 0; p < particles; ++p) {
    const int frame = p / int(slots_per_frame), slot = p % int(slots_per_frame);
    const int a = first + value_step_per_frame * frame + 2 * slot;
    values.push_back({{a, a + 1}});
  }
  container.append(supercell, values);
}

// ---- "Alle Particle in einem Frame" ---------------------------------------------------------

struct DoubleAndTriple {
  unisph::View<Frame> frame;
  UNISPH_HOST_DEVICE void operator()(Index) const {
    const Index jumpsize = 1, offset = 0, nbElem = 10;
    const RuntimeTuple runtime_frame{offset, nbElem, jumpsize};
    ParticlesInFrame<> view(frame[0], runtime_frame);
    for (auto it = view.begin(); it != view.end(); ++it) {
      auto wrapper = *it;
      if (wrapper) {
        (*wrapper).data[0] *= 2;
        (*wrapper).data[1] *= 3;
      }
    }
  }
};

UNISPH_POLICY_TEST_SUITE(SlideExamples);

TYPED_TEST(SlideExamples, DoublesAndTriplesTheParticlesOfAFrame) {
  DiscreteVariable<Frame> frame("frame", 1);
  {
    Frame& host = frame.write(MemorySpace::host)[0];
    for (int s = 0; s < 5; ++s) host.slots[s] = {{2 * s, 2 * s + 1}};
    EXPECT_EQ(print(host, 5), "[(0, 1), (2, 3), (4, 5), (6, 7), (8, 9)]");
  }
  // nbElem = 10 on the slide, but a frame has 5 slots: the count comes from the frame's type.
  EXPECT_EQ(ParticlesInFrame<>(frame.read_write(MemorySpace::host)[0], RuntimeTuple{0, 10, 1}).element_count(), 5u);
  particle_for(this->policy, 1, DoubleAndTriple{frame.read_write(this->policy)});
  EXPECT_EQ(print(frame.read(MemorySpace::host)[0], 5), "[(0, 3), (4, 9), (8, 15), (12, 21), (16, 27)]");
}

// ---- "Jedes zweite Frame in einer Superzelle" -----------------------------------------------

template <class Direction>
struct RecordEverySecondFrame {
  Supercells cells;
  unisph::View<Index> visited;  // pool indices of the frames, in visiting order; visited[0] = how many
  UNISPH_HOST_DEVICE void operator()(Index) const {
    const Index offset = 0, jumpsize = 2, nbElements = all;  // the slide writes nbElements = -1
    const RuntimeTuple runtime_supercell{offset, nbElements, jumpsize};
    FramesOfSupercell<Direction> view(cells[0], runtime_supercell);
    Index n = 0;
    for (auto it = view.begin(); it != view.end(); ++it)
      if (*it) visited[1 + n++] = Index(&**it - cells.frames);
    visited[0] = n;
  }
};

// The supercell of "Jedes zweite Frame": 5 frames, 22 particles.
void fill_every_second_frame_supercell(Container& container) { fill_supercell(container, 0, 22, 0, 20); }

template <class Direction, class Policy>
std::string every_second_frame(Policy policy, Container& container) {
  DiscreteVariable<Index> visited("visited", 8);
  particle_for(policy, 1, RecordEverySecondFrame<Direction>{container.read_write(policy), visited.write(policy)});
  const std::vector<Index> frames = visited.to_vector();
  const Supercells host = container.read_write(MemorySpace::host);
  std::string text;
  for (Index k = 0; k < frames[0]; ++k) text += "Frame: " + print(host.frames[frames[1 + k]], host[0].fill_of(frames[1 + k])) + "\n";
  return text;
}

TYPED_TEST(SlideExamples, VisitsEverySecondFrameOfASupercellForwardAndBackward) {
  Container container("slide", 1);
  fill_every_second_frame_supercell(container);
  EXPECT_EQ(print(container, 0),
            "[(0, 1), (2, 3), (4, 5), (6, 7), (8, 9)]\n"
            "[(20, 21), (22, 23), (24, 25), (26, 27), (28, 29)]\n"
            "[(40, 41), (42, 43), (44, 45), (46, 47), (48, 49)]\n"
            "[(60, 61), (62, 63), (64, 65), (66, 67), (68, 69)]\n"
            "[(80, 81), (82, 83), (-1, -1), (-1, -1), (-1, -1)]\n");
  const std::string first = "Frame: [(0, 1), (2, 3), (4, 5), (6, 7), (8, 9)]\n";
  const std::string third = "Frame: [(40, 41), (42, 43), (44, 45), (46, 47), (48, 49)]\n";
  const std::string fifth = "Frame: [(80, 81), (82, 83), (-1, -1), (-1, -1), (-1, -1)]\n";
  // The slide's printed result, first to last.
  EXPECT_EQ(every_second_frame<direction::Forward>(this->policy, container), first + third + fifth);
  // The slide's declared direction: the same frames, last first.
  EXPECT_EQ(every_second_frame<direction::Backward>(this->policy, container), fifth + third + first);
}

// ---- "Particle jedes zweiten Frames einer Superzelle" -----------------------------------------

template <class Direction>
struct RecordParticlesOfEverySecondFrame {
  Supercells cells;
  unisph::View<Particle> particles;
  unisph::View<Index> count;
  UNISPH_HOST_DEVICE void operator()(Index) const {
    using PartInFrame = ParticlesInFrame<>;
    // As on the slide: RuntimeTuple(0, -1, 2) for the frames, (0, 2, 1) for the particles.
    ParticlesOfSupercell<Direction> view(cells[0], RuntimeTuple{0, all, 2}, PartInFrame(nullptr, RuntimeTuple{0, 2, 1}));
    Index n = 0;
    for (auto it = view.begin(); it != view.end(); ++it)
      if (*it) particles[n++] = **it;
    count[0] = n;
  }
};

template <class Direction, class Policy>
std::string particles_of_every_second_frame(Policy policy, Container& container) {
  DiscreteVariable<Particle> particles("particles", 25);
  DiscreteVariable<Index> count("count", 1);
  particle_for(policy, 1,
               RecordParticlesOfEverySecondFrame<Direction>{container.read_write(policy), particles.write(policy),
                                                            count.write(policy)});
  const std::vector<Particle> found = particles.to_vector();
  std::string text = "Particles: ";
  for (Index k = 0; k < count.to_vector()[0]; ++k) text += (k > 0 ? ", " : "") + print(found[k]);
  return text;
}

TYPED_TEST(SlideExamples, VisitsTheParticlesOfEverySecondFrame) {
  Container container("slide", 1);
  fill_every_second_frame_supercell(container);
  EXPECT_EQ(particles_of_every_second_frame<direction::Forward>(this->policy, container),
            "Particles: (0, 1), (2, 3), (4, 5), (6, 7), (8, 9), (40, 41), (42, 43), (44, 45), (46, 47), (48, 49), "
            "(80, 81), (82, 83)");
  EXPECT_EQ(particles_of_every_second_frame<direction::Backward>(this->policy, container),
            "Particles: (80, 81), (82, 83), (40, 41), (42, 43), (44, 45), (46, 47), (48, 49), (0, 1), (2, 3), "
            "(4, 5), (6, 7), (8, 9)");
}

// ---- "Particle-Particle Interaktionen" ------------------------------------------------------

struct InteractTwoSupercells {
  Supercells supercell_container;
  UNISPH_HOST_DEVICE void operator()(Index) const {
    using ParticleInFrameView = ParticlesInFrame<>;
    const RuntimeTuple runtime_supercell1{0, all, 1}, runtime_supercell2{0, all, 1};
    const RuntimeTuple runtime_var_particle1{0, all, 1}, runtime_var_particle2{0, all, 1};
    ParticlesOfSupercell<direction::Forward> iter_super_cell1(supercell_container[0], runtime_supercell1,
                                                              ParticleInFrameView(nullptr, runtime_var_particle1));
    ParticlesOfSupercell<direction::Forward> iter_super_cell2(supercell_container[1], runtime_supercell2,
                                                              ParticleInFrameView(nullptr, runtime_var_particle2));
    for (auto it = iter_super_cell1.begin(); it != iter_super_cell1.end(); ++it) {
      if (*it) (**it).data[0] = 0;
      for (auto it2 = iter_super_cell2.begin(); it2 != iter_super_cell2.end(); ++it2)
        if (*it and *it2)  // check whether both are valid
          (**it).data[0] += (**it2).data[1];
    }
  }
};

// The slide after it: every pair of valid particles of the first supercell agrees on data[0].
struct CountDisagreements {
  Supercells supercell_container;
  unisph::View<int> errors;
  UNISPH_HOST_DEVICE void operator()(Index) const {
    ParticlesOfSupercell<direction::Forward> iter_super_cell1(supercell_container[0], RuntimeTuple{},
                                                              ParticlesInFrame<>(nullptr, RuntimeTuple{}));
    int count = 0;
    for (auto it = iter_super_cell1.begin(); it != iter_super_cell1.end(); ++it)
      for (auto it2 = iter_super_cell1.begin(); it2 != iter_super_cell1.end(); ++it2)
        if (*it and *it2)
          if ((**it).data[0] != (**it2).data[0]) ++count;  // the slide prints "Error"
    errors[0] = count;
  }
};

// The two supercells of the interaction slides: 5 frames with 22 particles, 4 frames with 19.
void fill_interaction_supercells(Container& container) {
  fill_supercell(container, 0, 22, 0, 10);
  fill_supercell(container, 1, 19, 50, 10);
}

TYPED_TEST(SlideExamples, ParticleParticleInteractionBetweenTwoSupercells) {
  Container container("interaction", 2);
  fill_interaction_supercells(container);
  EXPECT_EQ(print(container, 0),
            "[(0, 1), (2, 3), (4, 5), (6, 7), (8, 9)]\n"
            "[(10, 11), (12, 13), (14, 15), (16, 17), (18, 19)]\n"
            "[(20, 21), (22, 23), (24, 25), (26, 27), (28, 29)]\n"
            "[(30, 31), (32, 33), (34, 35), (36, 37), (38, 39)]\n"
            "[(40, 41), (42, 43), (-1, -1), (-1, -1), (-1, -1)]\n");
  const std::string second =
      "[(50, 51), (52, 53), (54, 55), (56, 57), (58, 59)]\n"
      "[(60, 61), (62, 63), (64, 65), (66, 67), (68, 69)]\n"
      "[(70, 71), (72, 73), (74, 75), (76, 77), (78, 79)]\n"
      "[(80, 81), (82, 83), (84, 85), (86, 87), (-1, -1)]\n";
  EXPECT_EQ(print(container, 1), second);
  DiscreteVariable<int> errors("errors", 1);
  // Before the interaction the first supercell's data[0] differ: 22 * 21 ordered pairs disagree.
  particle_for(this->policy, 1, CountDisagreements{container.read_write(this->policy), errors.write(this->policy)});
  EXPECT_EQ(errors.to_vector()[0], 22 * 21);

  particle_for(this->policy, 1, InteractTwoSupercells{container.read_write(this->policy)});
  EXPECT_EQ(print(container, 0),
            "[(1311, 1), (1311, 3), (1311, 5), (1311, 7), (1311, 9)]\n"
            "[(1311, 11), (1311, 13), (1311, 15), (1311, 17), (1311, 19)]\n"
            "[(1311, 21), (1311, 23), (1311, 25), (1311, 27), (1311, 29)]\n"
            "[(1311, 31), (1311, 33), (1311, 35), (1311, 37), (1311, 39)]\n"
            "[(1311, 41), (1311, 43), (-1, -1), (-1, -1), (-1, -1)]\n");
  EXPECT_EQ(print(container, 1), second);  // read only
  particle_for(this->policy, 1, CountDisagreements{container.read_write(this->policy), errors.write(this->policy)});
  EXPECT_EQ(errors.to_vector()[0], 0);
}

// ---- the five threads of the last slide -----------------------------------------------------
//
// How many invalid slots do they meet? Each of T = 5 threads walks every frame of the supercell
// (frame jump 1) and, within a frame of N = 5 slots, the slots id, id + T, ... with
// ceil(N / T) = 1 trip per frame (iter/view.hpp: the trip count is the same for every offset
// below the jump). All threads together therefore make frames * T * ceil(N / T) trips; each
// valid particle is met exactly once, every other trip meets an invalid slot:
//   invalid = frames * T * ceil(N / T) - particles.
// The slide's cell is the second supercell (runtimeSupercell2): 4 frames, 19 particles, so
// 4 * 5 * 1 - 19 = 1 (slot 4 of the last frame, met by thread 4). For the first supercell
// (5 frames, 22 particles) it is 25 - 22 = 3. Afterwards every particle's data[0] is the id of
// the thread that met it: its slot number.

constexpr int invalid_slots_met(int frames, int threads, int particles) {
  return frames * threads * ((int(slots_per_frame) + threads - 1) / threads) - particles;
}
static_assert(invalid_slots_met(4, 5, 19) == 1 && invalid_slots_met(5, 5, 22) == 3);

// The slide's code: the five threads one after another (Collectivity::None, offset = id,
// jump = nbThreads, and the frame's element count, which the view ignores, set to nbElemsLastFrame).
struct FiveThreadsOneAfterAnother {
  Supercells supercell_container;
  Index supercell;
  unisph::View<int> invalid;
  UNISPH_HOST_DEVICE void operator()(Index) const {
    const iter::Supercell<Frame> cell = supercell_container[supercell];
    const RuntimeTuple runtime_supercell2{0, all, 1};
    const Index nb_threads = 5;
    int count = 0;
    for (Index id = 0; id < nb_threads; ++id) {
      ParticlesOfSupercell<direction::Forward> iter_super_cell(
          cell, runtime_supercell2, ParticlesInFrame<>(nullptr, RuntimeTuple{id, cell.header.particles_in_last_frame, nb_threads}));
      for (auto it = iter_super_cell.begin(); it != iter_super_cell.end(); ++it)
        if (*it)
          (**it).data[0] = int(id);
        else
          ++count;
    }
    invalid[0] = count;
  }
};

// The same five threads at the same time: a team of 5 (std::threads with a barrier on the host,
// a block of 5 CUDA threads on the device) shares the walk through its collectivity, and meets
// at a barrier on every trip, which is safe only because every thread makes the same number of trips.
struct FiveThreadsAsATeam {
  Supercells supercell_container;
  unisph::View<int> invalid;
  unisph::View<int> trips;
  template <class Team>
  UNISPH_HOST_DEVICE void operator()(const Team& team, Index supercell) const {
    using PartInFrame = iter::View<Frame, direction::Forward, Team, RuntimeTuple>;
    iter::View<iter::Supercell<Frame>, direction::Forward, collectivity::None, RuntimeTuple, PartInFrame> view(
        supercell_container[supercell], RuntimeTuple{}, PartInFrame(nullptr, RuntimeTuple{}, iter::NoChild{}, team));
    for (auto it = view.begin(); it != view.end(); ++it) {
      if (*it)
        (**it).data[0] = int(team.rank());
      else
        atomic_add(&invalid[supercell], 1);
      atomic_add(&trips[supercell * 8 + team.rank()], 1);
      team.sync();
    }
  }
};

TYPED_TEST(SlideExamples, FiveThreadsShareATraversalAndCountTheInvalidSlots) {
  const std::string after =
      "[(0, 51), (1, 53), (2, 55), (3, 57), (4, 59)]\n"
      "[(0, 61), (1, 63), (2, 65), (3, 67), (4, 69)]\n"
      "[(0, 71), (1, 73), (2, 75), (3, 77), (4, 79)]\n"
      "[(0, 81), (1, 83), (2, 85), (3, 87), (-1, -1)]\n";
  {
    Container container("interaction", 2);
    fill_interaction_supercells(container);
    DiscreteVariable<int> invalid("invalid", 1);
    particle_for(this->policy, 1, FiveThreadsOneAfterAnother{container.read_write(this->policy), 1, invalid.write(this->policy)});
    EXPECT_EQ(invalid.to_vector()[0], invalid_slots_met(4, 5, 19));
    EXPECT_EQ(print(container, 1), after);
    particle_for(this->policy, 1, FiveThreadsOneAfterAnother{container.read_write(this->policy), 0, invalid.write(this->policy)});
    EXPECT_EQ(invalid.to_vector()[0], invalid_slots_met(5, 5, 22));
  }
  {
    Container container("interaction", 2);
    fill_interaction_supercells(container);
    DiscreteVariable<int> invalid("invalid", 2), trips("trips", 16);
    iter::collective_for(this->policy, 2, 5,
                         FiveThreadsAsATeam{container.read_write(this->policy), invalid.read_write(this->policy),
                                            trips.read_write(this->policy)});
    const std::vector<int> counted = invalid.to_vector(), made = trips.to_vector();
    EXPECT_EQ(counted[0], invalid_slots_met(5, 5, 22));
    EXPECT_EQ(counted[1], invalid_slots_met(4, 5, 19));
    for (int r = 0; r < 5; ++r) {
      EXPECT_EQ(made[0 * 8 + r], 5) << "thread " << r << " in the first supercell";
      EXPECT_EQ(made[1 * 8 + r], 4) << "thread " << r << " in the second supercell";
    }
    EXPECT_EQ(print(container, 1), after);
  }
}

}  // namespace
