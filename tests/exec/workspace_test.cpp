// WorkspaceScope: arrays taken in nested scopes keep their contents while inner scopes take more
// (on the device: while the workspace maps more memory behind it), algorithms run on them with
// their temporaries above, and a released block is taken again by the next scope.
#include <cstdint>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/workspace.hpp"

namespace {
using namespace unisph;

struct Fill {
  View<std::uint32_t> v;
  std::uint32_t mul, add;
  UNISPH_HOST_DEVICE void operator()(Index i) const { v[i] = mul * std::uint32_t(i) + add; }
};
struct Reverse {
  View<std::uint32_t> v;
  UNISPH_HOST_DEVICE void operator()(Index i) const { v[i] = std::uint32_t(v.size() - 1 - i); }
};
struct CopyOut {
  View<const std::uint32_t> from;
  View<std::uint32_t> to;
  UNISPH_HOST_DEVICE void operator()(Index i) const { to[i] = from[i]; }
};

template <class P>
std::vector<std::uint32_t> to_host(P policy, View<const std::uint32_t> v) {
  DiscreteVariable<std::uint32_t> out("out", v.size());
  particle_for(policy, v.size(), CopyOut{v, out.write(policy)});
  return out.to_vector();
}

UNISPH_POLICY_TEST_SUITE(Workspace);

TYPED_TEST(Workspace, OuterArraysSurviveInnerGrowthAndAlgorithms) {
  const auto policy = this->policy;
  DiscreteVariable<std::uint32_t> a_host("A"), b_host("B"), c_host("C"), d_host("D");
  WorkspaceScope outer(policy);
  const Index n = 1000;
  const View<std::uint32_t> a = outer.take(policy, a_host, n);
  particle_for(policy, n, Fill{a, 3, 1});
  const std::uint32_t* inner_block = nullptr;
  {
    // 2^25 keys and values (256 MiB with the sort's double buffers above them): more than the
    // workspace held, so it maps more behind `a`.
    WorkspaceScope inner(policy);
    const Index m = Index(1) << 25;
    const View<std::uint32_t> keys = inner.take(policy, b_host, m);
    const View<std::uint32_t> values = inner.take(policy, c_host, m);
    inner_block = keys.data();
    particle_for(policy, m, Reverse{keys});
    particle_for(policy, m, Fill{values, 1, 0});
    sort_pairs(policy, keys, values, 0, 32);
    const std::vector<std::uint32_t> k = to_host(policy, View<const std::uint32_t>(keys));
    const std::vector<std::uint32_t> v = to_host(policy, View<const std::uint32_t>(values));
    Index wrong = 0;
    for (Index i = 0; i < m; ++i) wrong += k[i] != std::uint32_t(i) || v[i] != std::uint32_t(m - 1 - i);
    EXPECT_EQ(wrong, 0u);
  }
  const std::vector<std::uint32_t> kept = to_host(policy, View<const std::uint32_t>(a));
  Index wrong = 0;
  for (Index i = 0; i < n; ++i) wrong += kept[i] != 3 * std::uint32_t(i) + 1;
  EXPECT_EQ(wrong, 0u) << "the outer scope's array changed while the inner scope grew the workspace";
  // The next scope takes the released block again (on the device; the host keeps each array's own variable).
  WorkspaceScope next(policy);
  const View<std::uint32_t> d = next.take(policy, d_host, 10);
  if constexpr (TypeParam::space == MemorySpace::device) {
    EXPECT_EQ(d.data(), inner_block);
  }
  particle_for(policy, 10, Fill{d, 2, 0});
  EXPECT_EQ(to_host(policy, View<const std::uint32_t>(d))[9], 18u);
}

}  // namespace
