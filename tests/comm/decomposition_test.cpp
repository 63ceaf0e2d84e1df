// Decomposition of a box among the ranks: every cell has one owner, the owner function agrees
// with the split keys and boxes, the weights are balanced, every rank decides the same.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "comm_test_support.hpp"
#include "unisph/comm/decomposition.hpp"

namespace {
using namespace unisph;
using namespace unisph::comm;

template <int D>
std::uint64_t fingerprint(const Decomposition<D>& d) {
  // Owners of every cell, hashed: equal on every rank when every rank decided the same.
  std::uint64_t h = 1469598103934665603ull;
  const CellGrid<D>& g = d.grid();
  Vec<int, D> c{};
  for (std::uint64_t k = 0; k < g.cell_count(); ++k) {
    std::uint64_t rest = k;
    for (int a = 0; a < D; ++a) {
      c[a] = static_cast<int>(rest % std::uint64_t(g.cells[a]));
      rest /= std::uint64_t(g.cells[a]);
    }
    h = (h ^ std::uint64_t(d.owner_of_cell(c) + 1)) * 1099511628211ull;
  }
  return h;
}

template <int D>
void check(DecompositionMethod method) {
  const Communicator comm = Communicator::world();
  const std::size_t n = D == 2 ? 20000 : 30000;
  const auto x = comm_test::global_positions<D>(n, 7 + D);
  const std::size_t b = comm_test::slice_begin(n, comm.rank(), comm.size());
  const std::size_t e = comm_test::slice_begin(n, comm.rank() + 1, comm.size());
  const std::span<const Vec<Real, D>> mine(x.data() + b, e - b);
  Box<Real, D> box{Vec<Real, D>::constant(0), Vec<Real, D>::constant(1)};
  Vec<int, D> periodic{};
  periodic[0] = 1;
  const CellGrid<D> grid = make_cell_grid(box, Real(D == 2 ? 0.02 : 0.05), periodic);
  const Decomposition<D> d = method == DecompositionMethod::morton ? decompose_morton(comm, grid, mine)
                                                                   : decompose_bisection(comm, grid, mine);
  EXPECT_EQ(d.ranks(), comm.size());
  EXPECT_EQ(comm.allreduce_min(fingerprint(d)), comm.allreduce_max(fingerprint(d)));

  // Every cell has an owner in range; the owner agrees with the split keys / boxes.
  std::vector<std::uint64_t> cells_of(std::size_t(comm.size()), 0);
  Vec<int, D> c{};
  for (std::uint64_t k = 0; k < grid.cell_count(); ++k) {
    std::uint64_t rest = k;
    for (int a = 0; a < D; ++a) {
      c[a] = static_cast<int>(rest % std::uint64_t(grid.cells[a]));
      rest /= std::uint64_t(grid.cells[a]);
    }
    const int o = d.owner_of_cell(c);
    if (o < 0 || o >= comm.size()) {  // no early return: the collectives below must run on every rank
      ADD_FAILURE() << "cell " << k << " has owner " << o;
      continue;
    }
    ++cells_of[std::size_t(o)];
    if (method == DecompositionMethod::morton) {
      const std::uint64_t key = morton_key<D>(c);
      EXPECT_LE(d.morton_splits()[std::size_t(o)], key);
      EXPECT_LT(key, d.morton_splits()[std::size_t(o) + 1]);
    } else {
      int containing = 0;
      for (const CellBox<D>& bx : d.boxes()) containing += bx.contains(c);
      EXPECT_EQ(containing, 1);
      EXPECT_TRUE(d.boxes()[std::size_t(o)].contains(c));
    }
  }
  // Every rank gets cells, and the particle counts are balanced (uniform particles).
  std::uint64_t owned = 0;
  for (const auto& p : x) owned += d.owner(p) == comm.rank();
  for (int r = 0; r < comm.size(); ++r) EXPECT_GT(cells_of[std::size_t(r)], 0u) << "rank " << r;
  EXPECT_EQ(comm.allreduce_sum(owned), n);
  const double imb = imbalance(comm, owned);
  EXPECT_GE(imb, 1.0);
  EXPECT_LT(imb, 1.1) << to_string(method) << " on " << comm.size() << " ranks";
  // The owner function wraps periodic axes and clamps the others.
  Vec<Real, D> inside = Vec<Real, D>::constant(Real(0.5)), wrapped = inside, clamped = inside;
  wrapped[0] += 1;
  clamped[D - 1] = Real(0.999);
  Vec<Real, D> beyond = clamped;
  beyond[D - 1] = Real(3.0);
  EXPECT_EQ(d.owner(wrapped), d.owner(inside));
  EXPECT_EQ(d.owner(beyond), d.owner(clamped));
}

TEST(HostDecomposition, Morton2D) { check<2>(DecompositionMethod::morton); }
TEST(HostDecomposition, Morton3D) { check<3>(DecompositionMethod::morton); }
TEST(HostDecomposition, Bisection2D) { check<2>(DecompositionMethod::bisection); }
TEST(HostDecomposition, Bisection3D) { check<3>(DecompositionMethod::bisection); }

TEST(HostDecomposition, WeightsMoveTheSplits) {
  const Communicator comm = Communicator::world();
  // Particles along x; those with x < 0.5 weigh 3: rank 0 of 2 gets less of the box.
  const std::size_t n = 4000;
  const auto x = comm_test::global_positions<2>(n, 99);
  std::vector<std::uint64_t> w(n);
  for (std::size_t i = 0; i < n; ++i) w[i] = x[i][0] < 0.5 ? 3 : 1;
  const std::size_t b = comm_test::slice_begin(n, comm.rank(), comm.size());
  const std::size_t e = comm_test::slice_begin(n, comm.rank() + 1, comm.size());
  const CellGrid<2> grid = make_cell_grid(Box<Real, 2>{{{0, 0}}, {{1, 1}}}, Real(0.01));
  const auto d = decompose_bisection(comm, grid, std::span<const Vec<Real, 2>>(x.data() + b, e - b),
                                     std::span<const std::uint64_t>(w.data() + b, e - b));
  std::uint64_t weight = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (d.owner(x[i]) == comm.rank()) weight += w[i];
  EXPECT_LT(imbalance(comm, weight), 1.1);
}

TEST(HostDecomposition, MoreRanksThanCellsIsAnError) {
  const Communicator comm = Communicator::world();
  const CellGrid<2> grid = make_cell_grid(Box<Real, 2>{{{0, 0}}, {{1, 1}}}, Real(0.9));  // 1 cell
  const std::vector<Vec<Real, 2>> none;
  if (comm.size() > 1)
    EXPECT_THROW(decompose_bisection(comm, grid, std::span<const Vec<Real, 2>>(none)), Error);
  else
    EXPECT_NO_THROW(decompose_bisection(comm, grid, std::span<const Vec<Real, 2>>(none)));
}

}  // namespace
