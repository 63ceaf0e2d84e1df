// Morton reordering: keys without aliasing up to 2^21 cells per axis; after a sort every
// particle's variables still belong to its id (a per-id fingerprint), keys are in order,
// neighbour sets by id are unchanged, on every policy, 2D and 3D, float and double. The (cell,
// id) order: a cell list ordered by id is then in cell order, and visits every particle's
// neighbours in the same order (by id) as before the sort, through its indirection.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include "neighbor_scenarios.hpp"
#include "support/policy_test.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/neighbor/particle_sorter.hpp"
#include "unisph/particles/body.hpp"

namespace {
using namespace unisph;
using namespace unisph::testing;

TEST(HostMortonKey, InterleavesWithoutAliasing) {
  EXPECT_EQ(morton_key<3>({{1, 0, 0}}), 1u);
  EXPECT_EQ(morton_key<3>({{0, 1, 0}}), 2u);
  EXPECT_EQ(morton_key<3>({{0, 0, 1}}), 4u);
  EXPECT_EQ(morton_key<2>({{3, 1}}), 0b0111u);
  const int top = (1 << 21) - 1;
  EXPECT_EQ(morton_key<3>({{top, top, top}}), (std::uint64_t(1) << 63) - 1);
  EXPECT_EQ(morton_key<2>({{top, top}}), (std::uint64_t(1) << 42) - 1);
  // Coordinates that differ only in high bits (or by one axis) get different keys.
  std::mt19937 rng(1);
  std::uniform_int_distribution<int> c(0, top);
  std::set<std::uint64_t> keys;
  std::vector<Vec<int, 3>> cells;
  for (int k = 0; k < 20000; ++k) cells.push_back({{c(rng), c(rng), c(rng)}});
  for (int k = 0; k < 64; ++k) cells.push_back({{top - k % 2, top, k % 3 == 0 ? 0 : top}});
  std::set<std::vector<int>> distinct;
  for (const auto& v : cells) {
    keys.insert(morton_key<3>(v));
    distinct.insert({v[0], v[1], v[2]});
  }
  EXPECT_EQ(keys.size(), distinct.size());
  // Decoding each axis back from the key gives the coordinates.
  for (const auto& v : cells) {
    const std::uint64_t key = morton_key<3>(v);
    for (int a = 0; a < 3; ++a) {
      int back = 0;
      for (int b = 0; b < 21; ++b) back |= int((key >> (3 * b + a)) & 1u) << b;
      ASSERT_EQ(back, v[a]);
    }
  }
  EXPECT_EQ(morton_key_bits(3, 83), 21);
  EXPECT_EQ(morton_key_bits(2, 1 << 21), 42);
}

template <class T, int D>
double fingerprint(std::uint64_t id) {
  return std::sin(0.37 * double(id)) * 1000.0 + double(id % 97);
}

template <class T, int D, class P>
void check_sort(P policy, SortOrder order) {
  SCOPED_TRACE(std::to_string(D) + "D, " + (sizeof(T) == 4 ? "float" : "double") +
               (order == SortOrder::morton       ? ", Morton order"
                : order == SortOrder::cell_index ? ", cell order"
                                                 : ", cell then id order"));
  const Scenario<T, D> s = make_scenario<T, D>(Layout::random, 21);
  const Index n = s.positions.size();
  Body<T, D> body("Water", s.box, n, 3);  // 3 ghosts after the owned particles
  ParticleSet& set = body.particles();
  auto& print = set.add_variable<double>("Fingerprint", sortable_output_variable);
  auto& half = set.add_variable<Vec<T, D>>("HalfPosition", sortable_variable);
  {
    View<Vec<T, D>> x = body.positions().write(MemorySpace::host);
    View<double> f = print.write(MemorySpace::host);
    View<Vec<T, D>> h = half.write(MemorySpace::host);
    for (Index i = 0; i < n + 3; ++i) {
      x[i] = i < n ? s.positions[i] : Vec<T, D>::constant(T(0.5));
      f[i] = i < n ? fingerprint<T, D>(i) : -1.0;
      h[i] = x[i] * T(0.5);
    }
  }
  CellLinkedList<T, D> cells(body.positions(), s.box, s.cutoff);
  cells.build(policy);
  InnerRelation<T, D> inner(cells, SearchMethod::stored);
  inner.set_source_count(n);
  inner.update(policy);
  auto pairs_by_id = [&](InnerRelation<T, D>& rel) {
    const auto count = rel.stored_lists().counts().to_vector();
    const auto nb = rel.stored_lists().neighbors().to_vector();
    const auto id = set.ids().to_vector();
    std::set<std::pair<std::uint64_t, std::uint64_t>> pairs;
    for (Index i = 0; i < n; ++i)
      for (std::uint64_t k = 0; k < count[i]; ++k) {
        const std::uint32_t j = nb[rel.stored_lists().slot(i, k)];
        pairs.insert({id[i], j < n ? id[j] : ~std::uint64_t(0)});  // ghosts have no id
      }
    return pairs;
  };
  const auto before = pairs_by_id(inner);

  ParticleSorter<T, D> sorter(set, body.positions(), cells.grid(), 10, order);
  EXPECT_FALSE(sorter.sort_if_due(policy, 3));
  EXPECT_TRUE(sorter.sort_if_due(policy, 20));
  EXPECT_EQ(sorter.sorts(), 1u);

  const auto id = set.ids().to_vector();
  const auto f = print.to_vector();
  const auto x = body.positions().to_vector();
  const auto h = half.to_vector();
  const auto index_of_id = set.index_of_id().to_vector();
  // The sort's keys live only within it: each particle's key from where it lies now, ascending.
  std::vector<std::uint64_t> keys(n);
  for (Index i = 0; i < n; ++i) {
    const Vec<int, D> cell = cells.grid().place(x[i]).cell;
    keys[i] = order == SortOrder::cell_index_then_id
                  ? (std::uint64_t(cells.grid().linear_index(cell)) << sorter.id_bits()) | id[i]
                  : (order == SortOrder::morton ? morton_key<D>(cell) : cells.grid().linear_index(cell));
  }
  EXPECT_TRUE(std::is_sorted(keys.begin(), keys.end()));
  Index wrong = 0;
  std::vector<int> seen(n, 0);
  for (Index i = 0; i < n; ++i) {
    ASSERT_LT(id[i], n);
    ++seen[id[i]];
    wrong += f[i] != fingerprint<T, D>(id[i]);
    wrong += !(x[i] == s.positions[id[i]]);
    wrong += !(h[i] == s.positions[id[i]] * T(0.5));
    wrong += index_of_id[id[i]] != i;
  }
  if (order == SortOrder::cell_index_then_id) {
    EXPECT_GE(std::uint64_t(1) << sorter.id_bits(), n + 1);  // every id, and the out-of-range one
    EXPECT_LT(std::uint64_t(1) << sorter.id_bits(), 2 * (n + 1));
  }
  for (Index i = n; i < n + 3; ++i) wrong += f[i] != -1.0;  // ghosts untouched
  EXPECT_EQ(wrong, 0u);
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int v) { return v == 1; }));

  cells.build(policy);
  inner.update(policy);
  EXPECT_TRUE(pairs_by_id(inner) == before) << "neighbour pairs by id changed with the order";
  // The 3 ghosts sit after the owned particles, in the middle of the box: out of cell order.
  EXPECT_FALSE(cells.report().in_cell_order);
  if (order != SortOrder::morton) {
    CellLinkedList<T, D> owned_only(set.variable(position_tag<T, D>), s.box, s.cutoff);
    body.particles().set_ghost_count(0);
    owned_only.build(policy);
    EXPECT_TRUE(owned_only.report().in_cell_order);
    // Ordered by id: in cell order only where the ids ascend within each cell as well.
    owned_only.order_within_cells_by_id(set);
    owned_only.build(policy);
    if (order == SortOrder::cell_index_then_id) {
      EXPECT_TRUE(owned_only.report().in_cell_order);
      const auto particles = owned_only.particles().to_vector();
      Index moved = 0;
      for (Index k = 0; k < n; ++k) moved += particles[k] != k;
      EXPECT_EQ(moved, 0u);
    }
  }
}

UNISPH_POLICY_TEST_SUITE(MortonSort);

TYPED_TEST(MortonSort, EveryIdKeepsItsVariables) {
  for (SortOrder order : {SortOrder::morton, SortOrder::cell_index, SortOrder::cell_index_then_id}) {
    check_sort<float, 2>(this->policy, order);
    check_sort<double, 2>(this->policy, order);
    check_sort<float, 3>(this->policy, order);
    check_sort<double, 3>(this->policy, order);
  }
}

TYPED_TEST(MortonSort, NaNParticlesSortLast) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Box<double, 2> box{Vec<double, 2>{}, Vec<double, 2>::constant(1.0)};
  for (SortOrder order : {SortOrder::morton, SortOrder::cell_index, SortOrder::cell_index_then_id}) {
    Body<double, 2> body("Water", box, 4);
    body.positions().assign(std::vector<Vec<double, 2>>{{{0.9, 0.9}}, {{nan, 0.1}}, {{0.1, 0.1}}, {{0.5, 0.5}}});
    const SearchGrid<double, 2> grid = SearchGrid<double, 2>::make(box, 0.1);
    ParticleSorter<double, 2> sorter(body.particles(), body.positions(), grid, 1, order);
    sorter.sort(this->policy);
    EXPECT_EQ(body.particles().ids().to_vector(), (std::vector<std::uint64_t>{2, 3, 0, 1}));
  }
}

// Each particle's neighbours as a sequence of ids, in the order the direct search visits them.
template <class T, int D>
struct RecordNeighborIds {
  NeighborSearch<T, D> search;
  View<const std::uint64_t> ids;
  Index capacity;
  View<std::uint64_t> found;  // row by the source's id - first_id
  View<std::uint32_t> counts;
  std::uint64_t first_id;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    const std::uint64_t row = ids[i] - first_id;
    Index c = 0;
    search.for_each_neighbor(i, [&](Index j, const NeighborPair<T, D>&) {
      if (c < capacity) found[row * capacity + c] = ids[j];
      ++c;
    });
    counts[row] = static_cast<std::uint32_t>(c);
  }
};

template <class T, int D, class P>
std::vector<std::vector<std::uint64_t>> neighbor_ids_in_visit_order(P policy, InnerRelation<T, D>& inner,
                                                                    ParticleSet& set) {
  const Index n = set.owned_count(), capacity = 512;
  DiscreteVariable<std::uint64_t> found("found", n * capacity);
  DiscreteVariable<std::uint32_t> counts("counts", n);
  particle_for(policy, n,
               RecordNeighborIds<T, D>{inner.search(policy), set.ids().read(policy), capacity, found.write(policy),
                                       counts.write(policy), set.first_id()});
  const auto f = found.to_vector();
  const auto c = counts.to_vector();
  std::vector<std::vector<std::uint64_t>> rows(n);
  for (Index r = 0; r < n; ++r) {
    EXPECT_LE(c[r], capacity);
    rows[r].assign(f.begin() + r * capacity, f.begin() + r * capacity + std::min<Index>(c[r], capacity));
  }
  return rows;
}

// The order that makes several ranks agree with one: a cell list ordered by id visits each
// particle's neighbours in one order of ids whatever the arrangement of the particles (shuffled,
// in cell order with the ids shuffled within cells, or sorted by (cell, id): then through the
// contiguous path), with a direct search and with stored lists, cells of the cutoff and of half.
template <class T, int D, class P>
void check_visit_order(P policy, SearchMethod method, T split) {
  SCOPED_TRACE(std::to_string(D) + "D, " + (sizeof(T) == 4 ? "float" : "double") +
               (method == SearchMethod::direct ? ", direct" : ", stored") + ", cells of cutoff / " +
               std::to_string(int(split)));
  const Scenario<T, D> s = make_scenario<T, D>(Layout::clustered, 5);
  const Index n = s.positions.size();
  Body<T, D> body("Water", s.box, n, 0);
  ParticleSet& set = body.particles();
  body.positions().assign(s.positions);
  {  // shuffled: the index order is not the id order within any cell
    std::vector<std::uint32_t> shuffle(n);
    std::iota(shuffle.begin(), shuffle.end(), 0u);
    std::shuffle(shuffle.begin(), shuffle.end(), std::mt19937(3));
    DiscreteVariable<std::uint32_t> permutation("Shuffle");
    permutation.assign(shuffle);
    set.reorder(policy, permutation.read(policy));
  }
  CellLinkedList<T, D> cells(body.positions(), s.box, s.cutoff, OutsideParticles::clamp, s.cutoff / split);
  cells.order_within_cells_by_id(set);
  InnerRelation<T, D> inner(cells, method);
  auto visit = [&]() {
    cells.build(policy);
    inner.update(policy);
    return neighbor_ids_in_visit_order<T, D>(policy, inner, set);
  };
  const auto shuffled = visit();
  EXPECT_FALSE(cells.report().in_cell_order);
  ParticleSorter<T, D> by_cell(set, body.positions(), cells.grid(), 1, SortOrder::cell_index);
  by_cell.sort(policy);
  const auto in_cells = visit();
  EXPECT_FALSE(cells.report().in_cell_order) << "the ids within the cells are still shuffled";
  ParticleSorter<T, D> by_cell_and_id(set, body.positions(), cells.grid(), 1, SortOrder::cell_index_then_id);
  by_cell_and_id.sort(policy);
  const auto sorted = visit();
  EXPECT_TRUE(cells.report().in_cell_order);
  EXPECT_TRUE(in_cells == shuffled);
  EXPECT_TRUE(sorted == shuffled);
  Index pairs = 0;  // the comparison saw pairs
  for (const auto& row : sorted) pairs += row.size();
  EXPECT_GT(pairs, n);
}

TYPED_TEST(MortonSort, CellThenIdOrderVisitsNeighborsAsTheIdOrderedList) {
  for (SearchMethod method : {SearchMethod::direct, SearchMethod::stored})
    for (int split : {1, 2}) {
      check_visit_order<float, 2>(this->policy, method, float(split));
      check_visit_order<double, 3>(this->policy, method, double(split));
    }
}

}  // namespace
