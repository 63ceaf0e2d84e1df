// Particle sets: stable ids, owned particles and ghosts, and reordering that moves every
// sortable variable (of any element size) with its particle and leaves the rest alone.
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/particles/body.hpp"

namespace {
using namespace unisph;

struct Odd3 {  // a 3-byte element: reordered byte by byte
  unsigned char b[3];
};

UNISPH_POLICY_TEST_SUITE(ParticleSetReorder);

TYPED_TEST(ParticleSetReorder, ReorderMovesSortableVariablesWithTheirIds) {
  const auto policy = this->policy;
  const Index owned = 5000, ghosts = 7;
  ParticleSet set("Water", owned, ghosts, 1000);
  auto& mass = set.add_variable<double>("Mass", sortable_output_variable);
  auto& vel = set.add_variable<Vec<float, 3>>("Velocity", sortable_variable);
  auto& tag = set.add_variable<Odd3>("Tag", sortable_variable);
  auto& scratch = set.add_variable<int>("Scratch");  // not sortable: stays where it is
  ASSERT_EQ(mass.size(), owned + ghosts);
  {
    View<double> m = mass.write(MemorySpace::host);
    View<Vec<float, 3>> v = vel.write(MemorySpace::host);
    View<Odd3> t = tag.write(MemorySpace::host);
    View<int> s = scratch.write(MemorySpace::host);
    for (Index i = 0; i < owned + ghosts; ++i) {
      m[i] = 0.5 * double(i);
      v[i] = {{float(i), float(2 * i), -float(i)}};
      t[i] = {{static_cast<unsigned char>(i), static_cast<unsigned char>(i >> 8), 7}};
      s[i] = int(i);
    }
  }
  std::vector<std::uint32_t> perm(owned);
  std::iota(perm.begin(), perm.end(), 0u);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(3));
  DiscreteVariable<std::uint32_t> p("perm");
  p.assign(perm);
  set.reorder(policy, p.read(policy));

  const auto id = set.ids().to_vector();
  const auto m = mass.to_vector();
  const auto v = vel.to_vector();
  const auto t = tag.to_vector();
  const auto s = scratch.to_vector();
  const auto index_of_id = set.index_of_id().to_vector();
  Index wrong = 0;
  for (Index k = 0; k < owned + ghosts; ++k) {
    // The original index of the particle now at k is its id - first id (ids start at 1000).
    const Index original = k < owned ? perm[k] : k;
    if (k < owned) {
      wrong += id[k] != 1000 + original;
      wrong += index_of_id[id[k] - 1000] != k;
    }
    wrong += m[k] != 0.5 * double(original);
    wrong += !(v[k] == Vec<float, 3>{{float(original), float(2 * original), -float(original)}});
    wrong += t[k].b[0] != static_cast<unsigned char>(original) || t[k].b[1] != static_cast<unsigned char>(original >> 8);
    wrong += s[k] != int(k);
  }
  EXPECT_EQ(wrong, 0u);
}

// A set made in shares (each rank its own particles of one whole set): the given particle
// numbers become ids, index_of_id() spans the whole set with the others absent; a set that
// drops the map keeps its ids through a reorder, and its id range.
TYPED_TEST(ParticleSetReorder, ShareOfAWholeSetKeepsItsNumbersAsIds) {
  const std::vector<std::uint64_t> numbers = {2, 5, 7, 8};
  ParticleSet share("Water", Index(numbers.size()), 0, 100, SetShare{10, numbers});
  EXPECT_EQ(share.id_count(), 10u);
  EXPECT_EQ(share.ids().to_vector(), (std::vector<std::uint64_t>{102, 105, 107, 108}));
  const std::vector<std::uint32_t> map = share.index_of_id().to_vector();
  ASSERT_EQ(map.size(), 10u);
  for (std::uint64_t k = 0; k < 10; ++k) {
    const auto at = std::find(numbers.begin(), numbers.end(), k);
    EXPECT_EQ(map[k], at == numbers.end() ? absent_particle_index : std::uint32_t(at - numbers.begin()));
  }
  DiscreteVariable<std::uint32_t> p("perm");
  p.assign(std::vector<std::uint32_t>{3, 1, 0, 2});
  share.reorder(this->policy, p.read(this->policy));
  EXPECT_EQ(share.index_of_id().to_vector()[8], 0u);  // number 8 moved to the front
  share.drop_index_of_id();
  EXPECT_EQ(share.index_of_id().size(), 0u);
  share.reorder(this->policy, p.read(this->policy));
  EXPECT_EQ(share.ids().to_vector(), (std::vector<std::uint64_t>{107, 105, 108, 102}));
  EXPECT_EQ(share.id_count(), 10u);
  EXPECT_THROW(ParticleSet("Bad", 2, 0, 0, SetShare{10, numbers}), Error);  // 4 numbers for 2 particles
  const std::vector<std::uint64_t> beyond = {3, 10};
  EXPECT_THROW(ParticleSet("Bad", 2, 0, 0, SetShare{10, beyond}), Error);  // number 10 of a set of 10
}

TYPED_TEST(ParticleSetReorder, WrongPermutationSizeIsAnError) {
  ParticleSet set("Water", 10);
  DiscreteVariable<std::uint32_t> p("perm", 9);
  EXPECT_THROW(set.reorder(this->policy, p.read(this->policy)), Error);
}

TEST(HostParticleSet, IdsGhostsAndBodies) {
  Body<double, 2> body("Wall", {Vec<double, 2>{}, Vec<double, 2>::constant(1.0)}, 4);
  ParticleSet& set = body.particles();
  EXPECT_EQ(set.ids().to_vector(), (std::vector<std::uint64_t>{0, 1, 2, 3}));
  EXPECT_EQ(body.positions().name(), "Position");
  EXPECT_TRUE(set.variables().entry("Position").flags.sortable);
  EXPECT_TRUE(set.variables().entry("ParticleId").flags.output);
  EXPECT_EQ(&set.variable(position_tag<double, 2>), &body.positions());
  set.set_ghost_count(3);
  EXPECT_EQ(set.total_count(), 7u);
  EXPECT_EQ(body.positions().size(), 7u);
  EXPECT_EQ(set.ids().to_vector()[3], 3u);
  EXPECT_THROW(set.variable<float>("Position"), VariableError);
}

}  // namespace
