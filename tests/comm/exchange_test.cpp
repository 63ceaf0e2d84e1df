// Migration and halo exchange of random particle sets against a brute-force reference, on
// every policy: every particle ends on its owner with all its sortable variables; every ghost
// a rank needs is there exactly once (at subdomain corners too), periodic images carry the
// shifted position; a refresh sends only the named variables.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <tuple>
#include <vector>

#include "comm_test_support.hpp"
#include "support/policy_test.hpp"
#include "unisph/comm/halo.hpp"
#include "unisph/comm/interior_split.hpp"
#include "unisph/comm/migrate.hpp"

namespace {
using namespace unisph;
using namespace unisph::comm;

struct Flag {  // a 1-byte element: packed byte by byte
  unsigned char v;
};

template <int D>
struct Scenario {
  Communicator comm = Communicator::world();
  std::size_t n;
  std::vector<Vec<Real, D>> global;
  CellGrid<D> grid;
  Real cutoff;
  VariableRegistry vars{"comm test", 0};
  Index owned = 0;

  Scenario(std::size_t count, Real cut, Vec<int, D> periodic, std::uint32_t seed) : n(count), cutoff(cut) {
    global = comm_test::global_positions<D>(n, seed);
    grid = make_cell_grid(Box<Real, D>{Vec<Real, D>::constant(0), Vec<Real, D>::constant(1)}, cutoff, periodic);
    const std::size_t b = comm_test::slice_begin(n, comm.rank(), comm.size());
    const std::size_t e = comm_test::slice_begin(n, comm.rank() + 1, comm.size());
    owned = e - b;
    vars.resize(owned);
    auto& x = vars.add<Vec<Real, D>>("Position", sortable_variable);
    auto& id = vars.add<std::uint64_t>("ParticleId", sortable_variable);
    auto& mass = vars.add<double>("Mass", sortable_variable);
    auto& flag = vars.add<Flag>("Flag", sortable_variable);
    vars.add<float>("Scratch");  // not sortable: does not travel
    View<Vec<Real, D>> xh = x.write(MemorySpace::host);
    View<std::uint64_t> idh = id.write(MemorySpace::host);
    View<double> mh = mass.write(MemorySpace::host);
    View<Flag> fh = flag.write(MemorySpace::host);
    for (Index k = 0; k < owned; ++k) {
      xh[k] = global[b + k];
      idh[k] = b + k;
      mh[k] = comm_test::mass_of(b + k);
      fh[k] = Flag{static_cast<unsigned char>((b + k) % 251)};
    }
  }
  // This rank's slice of the global particles, where it starts the test.
  std::size_t slice_begin() const { return comm_test::slice_begin(n, comm.rank(), comm.size()); }
  std::size_t slice_end() const { return comm_test::slice_begin(n, comm.rank() + 1, comm.size()); }
  // The decomposition of the starting slices (collective).
  Decomposition<D> decompose(DecompositionMethod method) const {
    const std::span<const Vec<Real, D>> start(global.data() + slice_begin(), slice_end() - slice_begin());
    return method == DecompositionMethod::morton ? decompose_morton(comm, grid, start)
                                                 : decompose_bisection(comm, grid, start);
  }
  View<const Vec<Real, D>> positions() {
    return View<const Vec<Real, D>>(vars.template get<Vec<Real, D>>("Position").read(MemorySpace::host).data(), owned);
  }
};

template <int D, class P>
void migrate_and_check(P policy, Scenario<D>& s, DecompositionMethod method, TransportKind kind) {
  const Decomposition<D> d = s.decompose(method);
  auto transport = make_transport(kind, s.comm);
  VariableExchange exchange;
  wrap_into_box(policy, s.grid, s.vars.template get<Vec<Real, D>>("Position"), s.owned);
  const Plan plan = migration_plan(s.comm, d, s.positions());
  s.owned = migrate(policy, *transport, plan, s.vars, s.owned, exchange);
  ASSERT_EQ(s.vars.size(), s.owned);

  // Brute force: the ids this rank must own, each with its values.
  std::vector<std::uint64_t> expected;
  for (std::size_t i = 0; i < s.n; ++i)
    if (d.owner(s.global[i]) == s.comm.rank()) expected.push_back(i);
  std::vector<std::uint64_t> got = s.vars.template get<std::uint64_t>("ParticleId").to_vector();
  auto xs = s.vars.template get<Vec<Real, D>>("Position").to_vector();
  auto ms = s.vars.template get<double>("Mass").to_vector();
  auto fs = s.vars.template get<Flag>("Flag").to_vector();
  int wrong = 0;
  for (Index k = 0; k < s.owned; ++k) {
    const std::uint64_t id = got[k];
    if (id >= s.n) {
      ++wrong;
      continue;
    }
    for (int a = 0; a < D; ++a) wrong += xs[k][a] != s.global[id][a];
    wrong += ms[k] != comm_test::mass_of(id);
    wrong += fs[k].v != id % 251;
  }
  EXPECT_EQ(wrong, 0);
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, expected);
  EXPECT_EQ(s.comm.allreduce_sum(std::uint64_t(s.owned)), s.n);
  // A second migration moves nothing.
  const Plan again = migration_plan(s.comm, d, s.positions());
  EXPECT_EQ(again.export_count(), 0u);
  EXPECT_EQ(again.import_count(), 0u);
}

UNISPH_POLICY_TEST_SUITE(CommMigrate);

TYPED_TEST(CommMigrate, RandomParticlesReachTheirOwners2DMorton) {
  Scenario<2> s(3000, Real(0.05), Vec<int, 2>{{1, 0}}, 11);
  migrate_and_check(this->policy, s, DecompositionMethod::morton, default_transport(TypeParam::space));
}
TYPED_TEST(CommMigrate, RandomParticlesReachTheirOwners3DBisection) {
  Scenario<3> s(4000, Real(0.1), Vec<int, 3>{{0, 1, 1}}, 12);
  migrate_and_check(this->policy, s, DecompositionMethod::bisection, default_transport(TypeParam::space));
}
TYPED_TEST(CommMigrate, HostStagedTransportByName) {
  Scenario<3> s(2000, Real(0.1), Vec<int, 3>{}, 13);
  migrate_and_check(this->policy, s, DecompositionMethod::morton, parse_transport("host_staged"));
}

// Brute force: the ghosts rank `me` must receive, as (id, image) sorted.
template <int D>
std::vector<std::tuple<std::uint64_t, Vec<int, D>>> expected_ghosts(const Scenario<D>& s, const Decomposition<D>& d,
                                                                     int me) {
  const CellGrid<D>& g = s.grid;
  std::vector<Vec<int, D>> my_cells;
  Vec<int, D> c{};
  for (std::uint64_t k = 0; k < g.cell_count(); ++k) {
    std::uint64_t rest = k;
    for (int a = 0; a < D; ++a) {
      c[a] = static_cast<int>(rest % std::uint64_t(g.cells[a]));
      rest /= std::uint64_t(g.cells[a]);
    }
    if (d.owner_of_cell(c) == me) my_cells.push_back(c);
  }
  int images = 1;
  for (int a = 0; a < D; ++a) images *= 3;
  std::vector<std::tuple<std::uint64_t, Vec<int, D>>> out;
  for (std::size_t i = 0; i < s.n; ++i) {
    const int owner = d.owner(s.global[i]);
    for (int m = 0; m < images; ++m) {
      Vec<int, D> image{};
      bool ok = true;
      for (int a = 0, code = m; a < D; ++a, code /= 3) {
        image[a] = code % 3 - 1;
        if (image[a] != 0 && !g.periodic[a]) ok = false;
      }
      if (!ok) continue;
      bool zero = true;
      for (int a = 0; a < D; ++a) zero = zero && image[a] == 0;
      if (owner == me && zero) continue;
      Vec<Real, D> y = s.global[i];
      for (int a = 0; a < D; ++a) y[a] += static_cast<Real>(image[a]) * g.period()[a];
      bool near = false;
      for (const Vec<int, D>& cell : my_cells) {
        Real d2 = 0;
        for (int a = 0; a < D; ++a) {
          const Real lo = g.box.lower[a] + cell[a] * g.cell_size[a], hi = lo + g.cell_size[a];
          const Real gap = y[a] < lo ? lo - y[a] : (y[a] > hi ? y[a] - hi : Real(0));
          d2 += gap * gap;
        }
        if (d2 <= s.cutoff * s.cutoff) {
          near = true;
          break;
        }
      }
      if (near) out.emplace_back(i, image);
    }
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    if (std::get<0>(a) != std::get<0>(b)) return std::get<0>(a) < std::get<0>(b);
    for (int k = 0; k < D; ++k)
      if (std::get<1>(a)[k] != std::get<1>(b)[k]) return std::get<1>(a)[k] < std::get<1>(b)[k];
    return false;
  });
  return out;
}

// Every owned particle listed once, the interior ones ascending then the border ones; no particle
// of another rank, and no periodic image of any particle, within the cutoff of an interior one
// (by brute force over the whole set, with the nearest image along periodic axes).
// reach > 0: the finer split (InteriorSplit::build's reach), checked against a brute force of
// its own bound (no other rank's particle within the reach of an interior particle) and
// against the cells' split (every interior particle of the cells is interior here too).
template <int D>
void check_interior_split(Scenario<D>& s, const Decomposition<D>& d, InteriorSplit<D>& split, Real reach = 0) {
  const auto items = split.items(SequencedPolicy{});
  ASSERT_EQ(split.size(), s.owned);
  std::vector<int> seen(s.owned, 0);
  int order = 0;
  for (Index k = 0; k < items.size(); ++k) {
    ASSERT_LT(items[k], s.owned);
    ++seen[items[k]];
    if (k > 0 && k != split.interior_count()) order += items[k] <= items[k - 1];
  }
  EXPECT_EQ(order, 0) << "each part must be in index order";
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), std::ptrdiff_t(s.owned)) << "each owned particle once";
  const auto xs = s.vars.template get<Vec<Real, D>>("Position").to_vector();
  const int me = s.comm.rank();
  int reached = 0;
  for (Index k = 0; k < split.interior_count(); ++k) {
    const Vec<Real, D>& x = xs[items[k]];
    for (int a = 0; a < D; ++a)
      if (s.grid.periodic[a])
        reached += std::min(x[a] - s.grid.box.lower[a], s.grid.box.upper[a] - x[a]) < s.cutoff;
    for (std::size_t j = 0; j < s.n; ++j) {
      if (d.owner(s.global[j]) == me) continue;
      Real d2 = 0;
      for (int a = 0; a < D; ++a) {
        Real gap = std::abs(s.global[j][a] - x[a]);
        if (s.grid.periodic[a]) gap = std::min(gap, s.grid.period()[a] - gap);
        d2 += gap * gap;
      }
      const Real bound = reach > 0 ? reach : s.cutoff;
      reached += d2 < bound * bound;
    }
  }
  EXPECT_EQ(reached, 0) << "rank " << me << ": a ghost within the cutoff (or reach) of an interior particle";
  // As many interior particles as the host's table gives (none where every cell touches a
  // periodic face), and border particles wherever there are other ranks.
  Index interior = 0;
  for (Index k = 0; k < s.owned; ++k) interior += d.interior(s.grid.cell_of(xs[k]));
  if (reach > 0) {
    EXPECT_GE(split.interior_count(), interior);
    for (Index k = 0; k < split.border_count(); ++k)
      EXPECT_FALSE(d.interior(s.grid.cell_of(xs[items[split.interior_count() + k]])));
  } else {
    EXPECT_EQ(split.interior_count(), interior);
  }
  if (s.comm.size() > 1) EXPECT_GT(s.comm.allreduce_sum(std::uint64_t(split.border_count())), 0u);
}

template <int D, class P>
void halo_and_check(P policy, Scenario<D>& s, DecompositionMethod method) {
  const std::size_t b = s.slice_begin(), e = s.slice_end();
  const Decomposition<D> d = s.decompose(method);
  // UNISPH_TRANSPORT picks another transport (as in the solver), to compare them on one machine.
  const char* chosen = std::getenv("UNISPH_TRANSPORT");
  auto transport = make_transport(chosen && *chosen ? parse_transport(chosen) : default_transport(P::space), s.comm);
  VariableExchange exchange;
  const Plan plan = migration_plan(s.comm, d, s.positions());
  s.owned = migrate(policy, *transport, plan, s.vars, s.owned, exchange);

  Halo<D> halo(s.comm, d, s.positions(), s.cutoff);
  halo.gather(policy, *transport, s.vars, s.owned, "Position");
  ASSERT_EQ(s.vars.size(), s.owned + halo.ghost_count());

  const auto ids = s.vars.template get<std::uint64_t>("ParticleId").to_vector();
  const auto xs = s.vars.template get<Vec<Real, D>>("Position").to_vector();
  const auto ms = s.vars.template get<double>("Mass").to_vector();
  const auto fs = s.vars.template get<Flag>("Flag").to_vector();
  std::vector<std::tuple<std::uint64_t, Vec<int, D>>> got;
  int wrong = 0;
  for (Index k = s.owned; k < s.vars.size(); ++k) {
    const std::uint64_t id = ids[k];
    if (id >= s.n) {
      ++wrong;
      continue;
    }
    // The image from the position: it must be exactly the original shifted by whole periods.
    Vec<int, D> image{};
    for (int a = 0; a < D; ++a) {
      for (int m = -1; m <= 1; ++m)
        if (s.global[id][a] + static_cast<Real>(m) * s.grid.period()[a] == xs[k][a]) image[a] = m;
      Real shifted = s.global[id][a] + static_cast<Real>(image[a]) * s.grid.period()[a];
      wrong += shifted != xs[k][a];
    }
    wrong += ms[k] != comm_test::mass_of(id);
    wrong += fs[k].v != id % 251;
    got.emplace_back(id, image);
  }
  EXPECT_EQ(wrong, 0);
  const auto expected = expected_ghosts(s, d, s.comm.rank());
  auto sorted = got;
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) {
    if (std::get<0>(a) != std::get<0>(b)) return std::get<0>(a) < std::get<0>(b);
    for (int k = 0; k < D; ++k)
      if (std::get<1>(a)[k] != std::get<1>(b)[k]) return std::get<1>(a)[k] < std::get<1>(b)[k];
    return false;
  });
  EXPECT_EQ(sorted.size(), expected.size()) << "rank " << s.comm.rank();
  int mismatched = 0;
  for (std::size_t k = 0; k < std::min(sorted.size(), expected.size()); ++k) {
    mismatched += std::get<0>(sorted[k]) != std::get<0>(expected[k]);
    for (int a = 0; a < D; ++a) mismatched += std::get<1>(sorted[k])[a] != std::get<1>(expected[k])[a];
  }
  EXPECT_EQ(mismatched, 0) << "rank " << s.comm.rank();
  bool periodic = false;
  for (int a = 0; a < D; ++a) periodic = periodic || s.grid.periodic[a];
  if (s.comm.size() > 1 || periodic) {
    EXPECT_GT(s.comm.allreduce_sum(std::uint64_t(halo.ghost_count())), 0u);
  }

  // Refresh only the mass: owned masses doubled arrive in the ghosts; flags stay as they were.
  {
    View<double> m = s.vars.template get<double>("Mass").read_write(MemorySpace::host);
    View<Flag> f = s.vars.template get<Flag>("Flag").read_write(MemorySpace::host);
    for (Index k = 0; k < s.owned; ++k) {
      m[k] *= 2;
      f[k].v = 255;
    }
  }
  const std::vector<std::string> names{"Mass"};
  halo.refresh(policy, *transport, s.vars, s.owned, "Position", names);
  const auto ms2 = s.vars.template get<double>("Mass").to_vector();
  const auto fs2 = s.vars.template get<Flag>("Flag").to_vector();
  int stale = 0;
  for (Index k = s.owned; k < s.vars.size(); ++k) {
    stale += ms2[k] != 2 * comm_test::mass_of(ids[k]);
    stale += fs2[k].v != ids[k] % 251;
  }
  EXPECT_EQ(stale, 0);

  // The same in two halves around work on the interior particles: owned masses tripled arrive.
  {
    View<double> m = s.vars.template get<double>("Mass").read_write(MemorySpace::host);
    for (Index k = 0; k < s.owned; ++k) m[k] = 3 * comm_test::mass_of(ids[k]);
  }
  halo.refresh_begin(policy, *transport, s.vars, s.owned, "Position", names);
  InteriorSplit<D> split;
  split.build(policy, d, View<const Vec<Real, D>>(s.vars.template get<Vec<Real, D>>("Position").read(policy).data(), s.owned));
  halo.refresh_end(policy, s.owned);
  const auto ms3 = s.vars.template get<double>("Mass").to_vector();
  stale = 0;
  for (Index k = s.owned; k < s.vars.size(); ++k) stale += ms3[k] != 3 * comm_test::mass_of(ids[k]);
  EXPECT_EQ(stale, 0);
  check_interior_split(s, d, split);
  // The finer split, with the halo's reach (the cutoff here: the cells are as wide).
  InteriorSplit<D> finer;
  finer.build(policy, d, View<const Vec<Real, D>>(s.vars.template get<Vec<Real, D>>("Position").read(policy).data(), s.owned),
              s.cutoff);
  check_interior_split(s, d, finer, s.cutoff);
  const std::uint64_t coarse_total = s.comm.allreduce_sum(std::uint64_t(split.interior_count()));
  const std::uint64_t finer_total = s.comm.allreduce_sum(std::uint64_t(finer.interior_count()));
  if (s.comm.rank() == 0)
    std::printf("interior particles of %zu: %llu by the cells, %llu within the reach\n", std::size_t(s.n),
                static_cast<unsigned long long>(coarse_total), static_cast<unsigned long long>(finer_total));
}

UNISPH_POLICY_TEST_SUITE(CommHalo);

TYPED_TEST(CommHalo, Ghosts2DPeriodicXMorton) {
  Scenario<2> s(3000, Real(0.1), Vec<int, 2>{{1, 0}}, 21);
  halo_and_check(this->policy, s, DecompositionMethod::morton);
}
TYPED_TEST(CommHalo, Ghosts2DFullyPeriodicBisection) {
  Scenario<2> s(3000, Real(0.1), Vec<int, 2>{{1, 1}}, 22);
  halo_and_check(this->policy, s, DecompositionMethod::bisection);
}
TYPED_TEST(CommHalo, Ghosts3DPeriodicYZMorton) {
  Scenario<3> s(4000, Real(0.2), Vec<int, 3>{{0, 1, 1}}, 23);
  halo_and_check(this->policy, s, DecompositionMethod::morton);
}
TYPED_TEST(CommHalo, Ghosts3DNonPeriodicBisection) {
  Scenario<3> s(4000, Real(0.2), Vec<int, 3>{}, 24);
  halo_and_check(this->policy, s, DecompositionMethod::bisection);
}
// One cell along a periodic axis: a particle is its own image on both sides.
TYPED_TEST(CommHalo, Ghosts2DOneCellAcrossAPeriodicAxis) {
  Scenario<2> s(500, Real(0.6), Vec<int, 2>{{1, 0}}, 25);
  halo_and_check(this->policy, s, DecompositionMethod::morton);
}

// Halo on a ParticleSet: the ghosts are appended after its owned particles.
TYPED_TEST(CommHalo, ParticleSetGetsGhosts) {
  const auto policy = this->policy;
  const Communicator comm = Communicator::world();
  const std::size_t n = 1000;
  const auto global = comm_test::global_positions<2>(n, 31);
  const CellGrid<2> grid = make_cell_grid(Box<Real, 2>{{{0, 0}}, {{1, 1}}}, Real(0.1), Vec<int, 2>{{1, 1}});
  const Decomposition<2> d = decompose_morton(comm, grid, std::span<const Vec<Real, 2>>(global));  // every rank passes all: weights x P, same splits
  std::vector<Vec<Real, 2>> mine;
  std::vector<std::uint64_t> mine_ids;
  for (std::size_t i = 0; i < n; ++i)
    if (d.owner(global[i]) == comm.rank()) {
      mine.push_back(global[i]);
      mine_ids.push_back(i);
    }
  ParticleSet set("Water", mine.size());
  auto& x = set.add_variable<Vec<Real, 2>>("Position", sortable_variable);
  x.assign(mine);
  set.ids().assign(mine_ids);
  auto transport = make_transport(default_transport(TypeParam::space), comm);
  Halo<2> halo(comm, d, View<const Vec<Real, 2>>(x.read(MemorySpace::host).data(), set.owned_count()), Real(0.1));
  halo.gather(policy, *transport, set, "Position");
  EXPECT_EQ(set.ghost_count(), halo.ghost_count());
  EXPECT_EQ(x.size(), set.total_count());
  const auto ids = set.ids().to_vector();
  const auto xs = x.to_vector();
  int wrong = 0;
  for (Index k = set.owned_count(); k < set.total_count(); ++k) {
    if (ids[k] >= n) {
      ++wrong;
      continue;
    }
    const bool itself = d.owner(global[ids[k]]) == comm.rank() && xs[k][0] == global[ids[k]][0] &&
                        xs[k][1] == global[ids[k]][1];
    wrong += itself;  // a rank's own particle comes back only as a shifted periodic image
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(comm.allreduce_sum(std::uint64_t(set.ghost_count())) > 0, true);
}

// The plans built by kernels on the test's policy (positions in its memory, float as well as
// double) list the same items in the same order as those built on the host.
template <int D, class P, class S>
void plans_on_policy_equal_host(P policy, Scenario<D>& s, DecompositionMethod method) {
  const std::size_t b = s.slice_begin(), e = s.slice_end();
  const Decomposition<D> d = s.decompose(method);
  // Positions of this rank's slice (not yet migrated: many leave), in S on the policy.
  std::vector<Vec<S, D>> xs(e - b);
  std::vector<Vec<Real, D>> xr(e - b);
  for (std::size_t k = 0; k < xs.size(); ++k)
    for (int a = 0; a < D; ++a) {
      xs[k][a] = static_cast<S>(s.global[b + k][a]);
      xr[k][a] = static_cast<Real>(xs[k][a]);  // what the host sees of the same positions
    }
  DiscreteVariable<Vec<S, D>> x("Position");
  x.assign(xs);
  const View<const Vec<Real, D>> host(xr.data(), xr.size());

  const Plan m_host = migration_plan(s.comm, d, host);
  const Plan m_policy = migration_plan(policy, s.comm, d, View<const Vec<S, D>>(x.read(policy)));
  ASSERT_EQ(m_policy.export_count(), m_host.export_count());
  EXPECT_EQ(std::vector<std::uint32_t>(m_policy.export_index().begin(), m_policy.export_index().end()),
            std::vector<std::uint32_t>(m_host.export_index().begin(), m_host.export_index().end()));
  EXPECT_EQ(std::vector<std::int32_t>(m_policy.export_rank().begin(), m_policy.export_rank().end()),
            std::vector<std::int32_t>(m_host.export_rank().begin(), m_host.export_rank().end()));
  EXPECT_EQ(std::vector<std::int32_t>(m_policy.import_rank().begin(), m_policy.import_rank().end()),
            std::vector<std::int32_t>(m_host.import_rank().begin(), m_host.import_rank().end()));

  Halo<D, S> h_host(s.comm, d, host, s.cutoff);
  Halo<D, S> h_policy(policy, s.comm, d, View<const Vec<S, D>>(x.read(policy)), s.cutoff);
  const Plan& a = h_policy.plan();
  const Plan& c = h_host.plan();
  ASSERT_EQ(a.export_count(), c.export_count());
  EXPECT_EQ(a.import_count(), c.import_count());
  EXPECT_EQ(std::vector<std::uint32_t>(a.export_index().begin(), a.export_index().end()),
            std::vector<std::uint32_t>(c.export_index().begin(), c.export_index().end()));
  EXPECT_EQ(std::vector<std::int32_t>(a.export_rank().begin(), a.export_rank().end()),
            std::vector<std::int32_t>(c.export_rank().begin(), c.export_rank().end()));
  const auto sa = h_policy.shifts(), sc = h_host.shifts();
  int shifted = 0;
  for (std::size_t k = 0; k < sa.size(); ++k)
    for (int q = 0; q < D; ++q) shifted += sa[k][q] != sc[k][q];
  EXPECT_EQ(shifted, 0);
  bool periodic = false;
  for (int q = 0; q < D; ++q) periodic = periodic || s.grid.periodic[q];
  if (s.comm.size() > 1 || periodic) {
    EXPECT_GT(s.comm.allreduce_sum(std::uint64_t(a.export_count())), 0u);
  }
  // Built again in the same storage: the same plan.
  h_policy.build(policy, s.comm, d, View<const Vec<S, D>>(x.read(policy)), s.cutoff);
  EXPECT_EQ(std::vector<std::uint32_t>(h_policy.plan().export_index().begin(), h_policy.plan().export_index().end()),
            std::vector<std::uint32_t>(c.export_index().begin(), c.export_index().end()));
}

UNISPH_POLICY_TEST_SUITE(CommPlans);

TYPED_TEST(CommPlans, OnThePolicyAsOnTheHost2DPeriodicMorton) {
  Scenario<2> s(3000, Real(0.1), Vec<int, 2>{{1, 0}}, 41);
  plans_on_policy_equal_host<2, decltype(this->policy), Real>(this->policy, s, DecompositionMethod::morton);
}
TYPED_TEST(CommPlans, OnThePolicyAsOnTheHost3DFloatBisection) {
  Scenario<3> s(4000, Real(0.2), Vec<int, 3>{{0, 1, 1}}, 42);
  plans_on_policy_equal_host<3, decltype(this->policy), float>(this->policy, s, DecompositionMethod::bisection);
}
TYPED_TEST(CommPlans, OnThePolicyAsOnTheHost3DNonPeriodicMorton) {
  Scenario<3> s(4000, Real(0.15), Vec<int, 3>{}, 43);
  plans_on_policy_equal_host<3, decltype(this->policy), Real>(this->policy, s, DecompositionMethod::morton);
}

}  // namespace
