// Inner and contact relations against a brute-force O(N^2) search: every layout of
// neighbor_scenarios.hpp, 2D and 3D, float and double, direct search and stored lists, on
// every policy (so the sets are the same on every policy); out-of-box and NaN particles in
// both OutsideParticles modes; pairs whose decision a fused multiply-add would flip.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "neighbor_scenarios.hpp"
#include "support/policy_test.hpp"
#include "unisph/neighbor/contact_relation.hpp"
#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/particles/body.hpp"

namespace {
using namespace unisph;
using namespace unisph::testing;

using NeighborSets = std::vector<std::vector<std::uint32_t>>;

// Writes the neighbours of each source into a fixed-capacity row, and counts any pair whose
// r_ij, |r_ij| or e_ij is not what the positions say.
template <class T, int D>
struct CollectNeighbors {
  NeighborSearch<T, D> search;
  Index capacity;
  View<std::uint32_t> found;
  View<std::uint32_t> counts;
  View<unsigned> errors;
  bool cell_order = false;  // visit the sources in the cell list's order (cell_order_source)
  UNISPH_HOST_DEVICE void operator()(Index k) const {
    if (cell_order)
      visit(search.cell_order_source(k).particle, search.cell_order_source(k));
    else
      visit(k, k);
  }
  template <class Source>
  UNISPH_HOST_DEVICE void visit(Index i, Source source) const {
    Index c = 0;
    const Vec<T, D> xi = search.sources[i];
    search.for_each_neighbor(source, [&](Index j, const NeighborPair<T, D>& pair) {
      const Vec<T, D> r = xi - search.targets.positions[j];
      const T d = pair.distance();
      const Vec<T, D> e = pair.direction();
      const T e_norm2 = dot(e, e);
      const bool r_ok = r == pair.r_ij && pair.squared_distance < search.targets.grid.cutoff_squared;
      const bool d_ok = d >= T(0) && d < search.targets.grid.cutoff * T(1.0001);
      const bool e_ok = d == T(0) ? e_norm2 == T(0) : (e_norm2 > T(0.999) && e_norm2 < T(1.001));
      if (!(r_ok && d_ok && e_ok)) atomic_add(&errors[0], 1u);
      if (c < capacity) found[i * capacity + c] = static_cast<std::uint32_t>(j);
      ++c;
    });
    counts[i] = static_cast<std::uint32_t>(c);
  }
};

template <class T, int D, class P>
NeighborSets collect(P policy, NeighborSearch<T, D> search, Index sources, Index capacity, unsigned& errors,
                     bool cell_order = false) {
  DiscreteVariable<std::uint32_t> found("found", sources * capacity), counts("counts", sources);
  DiscreteVariable<unsigned> error_count("errors", 1);
  particle_for(policy, sources,
               CollectNeighbors<T, D>{search, capacity, found.write(policy), counts.write(policy),
                                      error_count.read_write(policy), cell_order});  // read_write: starts from zero
  const std::vector<std::uint32_t> f = found.to_vector(), c = counts.to_vector();
  errors = error_count.to_vector()[0];
  NeighborSets sets(sources);
  for (Index i = 0; i < sources; ++i) {
    sets[i].assign(f.begin() + i * capacity, f.begin() + i * capacity + std::min<Index>(c[i], capacity));
    if (c[i] > capacity) sets[i].push_back(~0u);  // overflow: never equal to the reference
    std::sort(sets[i].begin(), sets[i].end());
  }
  return sets;
}

// The reference: every pair tested, with the rules the relation documents.
template <class T, int D>
NeighborSets brute_force(const SearchGrid<T, D>& grid, const std::vector<Vec<T, D>>& sources,
                         const std::vector<Vec<T, D>>& targets, bool inner, bool flag_outside) {
  NeighborSets sets(sources.size());
  auto flagged = [&](const Vec<T, D>& x) { return flag_outside && grid.place(x).status != placement_inside; };
  for (Index i = 0; i < sources.size(); ++i) {
    if (inner && flagged(sources[i])) continue;
    for (Index j = 0; j < targets.size(); ++j) {
      if ((inner && i == j) || flagged(targets[j])) continue;
      Vec<T, D> r;
      T r2;
      if (grid.test_pair(sources[i], targets[j], r, r2)) sets[i].push_back(static_cast<std::uint32_t>(j));
    }
  }
  return sets;
}

Index capacity_for(const NeighborSets& reference) {
  Index most = 0;
  for (const auto& s : reference) most = std::max<Index>(most, s.size());
  return most + 1;
}

Index pair_count(const NeighborSets& sets) {
  Index n = 0;
  for (const auto& s : sets) n += s.size();
  return n;
}

template <class T, int D>
std::vector<Vec<T, D>> contact_sources(Index n) {
  std::mt19937_64 rng(99 + D);
  std::vector<Vec<T, D>> x;
  for (Index k = 0; k < n; ++k) x.push_back(random_point<T, D>(rng, -0.3, 1.3));  // some outside the box
  return x;
}

// Cells of cutoff / split: 1 is the default 3^D stencil; 2 and 3 search a wider stencil of
// smaller cells and skip the cells beyond the cutoff (the lattice then lies on cell faces too).
template <class T>
T cell_size_for(T cutoff, int split) {
  T size = cutoff / T(split);
  while (T(split) * size < cutoff) size = std::nextafter(size, cutoff);
  return size;
}

// The positions in cell order (the order ParticleSorter gives with SortOrder::cell_index).
template <class T, int D>
void sort_by_cell(Scenario<T, D>& s, T cell_size) {
  const SearchGrid<T, D> grid = SearchGrid<T, D>::make(s.box, s.cutoff, cell_size);
  std::stable_sort(s.positions.begin(), s.positions.end(), [&](const Vec<T, D>& a, const Vec<T, D>& b) {
    return grid.linear_index(grid.place(a).cell) < grid.linear_index(grid.place(b).cell);
  });
}

// The sources visited in the cell list's order with the positions copied into that order: the
// same sets as the reference, whatever the particles' own order (in cell order the copy is not
// written and the search takes the contiguous walk instead). Switches the copy off again.
template <class T, int D, class P>
void check_cell_ordered_positions(P policy, DiscreteVariable<Vec<T, D>>& x, CellLinkedList<T, D>& cells,
                                  const NeighborSets& expected) {
  cells.store_positions_in_cell_order();
  cells.build(policy);
  InnerRelation<T, D> inner(cells, SearchMethod::direct);
  unsigned errors = 0;
  const NeighborSets got = collect(policy, inner.search(policy), x.size(), capacity_for(expected), errors, true);
  EXPECT_EQ(errors, 0u);
  EXPECT_TRUE(got == expected) << "cell-ordered positions: " << pair_count(got) << " pairs, expected "
                               << pair_count(expected);
  cells.store_positions_in_cell_order(false);
  cells.build(policy);
}

template <class T, int D, class P>
void check_layouts(P policy) {
  for (int split : {1, 2, 3})
  for (Layout layout : all_layouts)
  for (bool cell_ordered : {false, true})
    for (SearchMethod method : {SearchMethod::direct, SearchMethod::stored}) {
      const std::string what = std::string(to_string(layout)) + (cell_ordered ? " in cell order, " : ", ") +
                               std::to_string(D) + "D, " + (sizeof(T) == 4 ? "float" : "double") +
                               (method == SearchMethod::direct ? ", direct search" : ", stored lists") +
                               ", cells of cutoff / " + std::to_string(split);
      SCOPED_TRACE(what);
      Scenario<T, D> s = make_scenario<T, D>(layout);
      const T cell_size = cell_size_for(s.cutoff, split);
      if (cell_ordered) sort_by_cell(s, cell_size);
      DiscreteVariable<Vec<T, D>> x("Position");
      x.assign(s.positions);
      CellLinkedList<T, D> cells(x, s.box, s.cutoff, OutsideParticles::clamp, cell_size);
      EXPECT_EQ(cells.grid().reach, split);
      cells.build(policy);
      InnerRelation<T, D> inner(cells, method);
      inner.update(policy);
      const NeighborSets expected = brute_force(cells.grid(), s.positions, s.positions, true, false);
      unsigned errors = 0;
      const NeighborSets got = collect(policy, inner.search(policy), x.size(), capacity_for(expected), errors);
      EXPECT_EQ(errors, 0u);
      EXPECT_TRUE(got == expected) << "inner: " << pair_count(got) << " pairs, expected " << pair_count(expected);
      if (method == SearchMethod::stored) {
        EXPECT_EQ(inner.stored_lists().pair_count(), pair_count(expected));
      } else {
        check_cell_ordered_positions(policy, x, cells, expected);
      }
      if (layout == Layout::lattice_on_faces) {  // 26 (3D) or 8 (2D) neighbours inside, pairs at the cutoff excluded
        EXPECT_EQ(expected[x.size() / 2].size(), D == 3 ? 26u : 8u);
      }

      const std::vector<Vec<T, D>> other = contact_sources<T, D>(D == 2 ? 300 : 500);
      DiscreteVariable<Vec<T, D>> y("Other");
      y.assign(other);
      ContactRelation<T, D> contact(y, cells, method);
      contact.update(policy);
      const NeighborSets expected_contact = brute_force(cells.grid(), other, s.positions, false, false);
      const NeighborSets got_contact =
          collect(policy, contact.search(policy), y.size(), capacity_for(expected_contact), errors);
      EXPECT_EQ(errors, 0u);
      EXPECT_TRUE(got_contact == expected_contact)
          << "contact: " << pair_count(got_contact) << " pairs, expected " << pair_count(expected_contact);
      if (cell_ordered) {
        EXPECT_TRUE(cells.report().in_cell_order);
      }
    }
}

// Counts the neighbours of each source through the kernel-shell path a method takes.
class CountNeighborsMethod : public InteractionDynamics<CountNeighborsMethod> {
 public:
  CountNeighborsMethod(InnerRelation<double, 3>& relation, DiscreteVariable<double>& count)
      : relation_(relation), count_(count) {}
  struct Kernel {
    NeighborSearch<double, 3> search;
    View<double> count;
    UNISPH_HOST_DEVICE void interaction(Index i, Real) const {
      double n = 0;
      search.for_each_neighbor(i, [&](Index, const NeighborPair<double, 3>&) { n += 1; });
      count[i] = n;
    }
  };
  Kernel make_kernel(KernelContext& context) { return {relation_.search(context), context.read_write(count_)}; }
  Index size() const { return relation_.source_count(); }

 private:
  InnerRelation<double, 3>& relation_;
  DiscreteVariable<double>& count_;
};

UNISPH_POLICY_TEST_SUITE(NeighborRelation);

// Owned particles find ghosts as neighbours; a method over the owned particles leaves the
// ghosts' values alone; the kernel follows the stored lists through every update.
TYPED_TEST(NeighborRelation, GhostsAreFoundButNotUpdated) {
  const auto policy = this->policy;
  const Scenario<double, 3> s = make_scenario<double, 3>(Layout::random);
  const Index ghosts = 100, owned = s.positions.size() - ghosts;
  Body<double, 3> body("Water", s.box, owned, ghosts);
  body.positions().assign(s.positions);
  auto& count = body.particles().add_variable<double>("NeighborCount", output_variable);
  {
    View<double> c = count.write(MemorySpace::host);
    for (Index i = 0; i < owned + ghosts; ++i) c[i] = -1.0;
  }
  CellLinkedList<double, 3> cells(body.positions(), body.domain(), s.cutoff);
  for (SearchMethod method : {SearchMethod::direct, SearchMethod::stored}) {
    InnerRelation<double, 3> inner(cells, method);
    inner.set_source_count(body.particles().owned_count());
    CountNeighborsMethod counting(inner, count);
    for (int step = 0; step < 2; ++step) {
      if (step == 1) {  // move the particles: the lists and the kernel must follow
        View<Vec<double, 3>> x = body.positions().read_write(MemorySpace::host);
        for (Index i = 0; i < owned + ghosts; ++i) x[i] = x[i] * 0.9;
      }
      cells.build(policy);
      inner.update(policy);
      counting.exec(policy);
      const auto x = body.positions().to_vector();
      const auto c = count.to_vector();
      const NeighborSets all = brute_force(cells.grid(), x, x, true, false);
      Index wrong = 0, ghost_neighbors = 0;
      for (Index i = 0; i < owned; ++i) {
        wrong += c[i] != double(all[i].size());
        for (std::uint32_t j : all[i]) ghost_neighbors += j >= owned;
      }
      for (Index i = owned; i < owned + ghosts; ++i) wrong += c[i] != -1.0;
      EXPECT_EQ(wrong, 0u) << (method == SearchMethod::direct ? "direct" : "stored") << ", step " << step;
      EXPECT_GT(ghost_neighbors, 0u);
    }
  }
}

template <class T, int D>
struct WriteSourceInCellOrder {
  NeighborSearch<T, D> search;
  View<std::uint32_t> out;
  UNISPH_HOST_DEVICE void operator()(Index k) const { out[k] = std::uint32_t(search.source_in_cell_order(k)); }
};

// source_in_cell_order visits every particle once, cell after cell, whatever the particles'
// own order; in cell order it is the identity.
TYPED_TEST(NeighborRelation, SourcesInCellOrderVisitEveryParticleOnceCellByCell) {
  const auto policy = this->policy;
  for (Layout layout : all_layouts) {
    const Scenario<float, 3> s = make_scenario<float, 3>(layout);
    std::vector<Vec<float, 3>> positions = s.positions;
    for (bool sorted : {false, true}) {
      DiscreteVariable<Vec<float, 3>> x("Position");
      CellLinkedList<float, 3> cells(x, s.box, s.cutoff);
      if (sorted)  // into cell order on the list's own grid
        std::stable_sort(positions.begin(), positions.end(), [&](const auto& a, const auto& b) {
          return cells.grid().linear_index(cells.grid().place(a).cell) < cells.grid().linear_index(cells.grid().place(b).cell);
        });
      x.assign(positions);
      cells.build(policy);
      InnerRelation<float, 3> inner(cells, SearchMethod::direct);
      const Index n = Index(positions.size());
      DiscreteVariable<std::uint32_t> order("order", n);
      particle_for(policy, n, WriteSourceInCellOrder<float, 3>{inner.search(policy), order.write(policy)});
      const std::vector<std::uint32_t> o = order.to_vector();
      std::vector<int> seen(n, 0);
      Index repeated = 0, out_of_order = 0, moved = 0;
      for (Index k = 0; k < n; ++k) {
        repeated += o[k] >= n || seen[o[k]]++ > 0;
        moved += o[k] != k;
        if (k > 0 && o[k] < n && o[k - 1] < n)
          out_of_order += cells.grid().linear_index(cells.grid().place(positions[o[k]]).cell) <
                          cells.grid().linear_index(cells.grid().place(positions[o[k - 1]]).cell);
      }
      EXPECT_EQ(repeated, 0u) << to_string(layout);
      EXPECT_EQ(out_of_order, 0u) << to_string(layout);
      if (sorted) {
        EXPECT_EQ(moved, 0u) << to_string(layout) << ": in cell order the order is the identity";
      }
    }
  }
}

TYPED_TEST(NeighborRelation, StoredListsMustBeUpdatedAfterEachBuild) {
  const auto policy = this->policy;
  const Scenario<double, 3> s = make_scenario<double, 3>(Layout::random);
  DiscreteVariable<Vec<double, 3>> x("Position");
  x.assign(s.positions);
  CellLinkedList<double, 3> cells(x, s.box, s.cutoff);
  cells.build(policy);
  InnerRelation<double, 3> inner(cells, SearchMethod::stored);
  EXPECT_THROW(inner.search(policy), Error);  // never updated
  inner.update(policy);
  EXPECT_NO_THROW(inner.search(policy));
  cells.build(policy);
  EXPECT_THROW(inner.search(policy), Error);  // the particles may have moved since
  inner.update(policy);
  EXPECT_NO_THROW(inner.search(policy));
  const SearchMethod expected_default =
      decltype(policy)::space == MemorySpace::device ? SearchMethod::direct : SearchMethod::stored;
  InnerRelation<double, 3> automatic(cells);
  EXPECT_EQ(automatic.method(policy), expected_default);
}

// A pair weight for the weighted loop (any function of the pair; SPH passes dW/dr).
struct ScaledDistance {
  double scale;
  template <class Pair>
  UNISPH_HOST_DEVICE double operator()(const Pair& pair) const { return scale * pair.distance(); }
};

// Counts the neighbours of the weighted loop and every w that is not weight(pair) bit for bit.
struct CheckWeights {
  NeighborSearch<double, 3> search;
  ScaledDistance weight;
  View<std::uint32_t> counts;
  View<unsigned> errors;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    std::uint32_t c = 0;
    search.for_each_weighted_neighbor(i, weight, [&](Index, const NeighborPair<double, 3>& pair, double w) {
      if (!(w == weight(pair))) atomic_add(&errors[0], 1u);
      ++c;
    });
    counts[i] = c;
  }
};

// The weight column of stored lists is handed to a search only for the functor that filled it
// and only for the lists it was filled for; the weighted loop gives the same neighbours and
// weight(pair) whether it reads the column or computes the weights.
TYPED_TEST(NeighborRelation, PairWeightsCachedForTheirFunctionOnly) {
  const auto policy = this->policy;
  const Scenario<double, 3> s = make_scenario<double, 3>(Layout::random);
  DiscreteVariable<Vec<double, 3>> x("Position");
  x.assign(s.positions);
  CellLinkedList<double, 3> cells(x, s.box, s.cutoff);
  const ScaledDistance weight{3.0}, other{2.0};
  for (SearchMethod method : {SearchMethod::direct, SearchMethod::stored}) {
    const bool stored = method == SearchMethod::stored;
    InnerRelation<double, 3> inner(cells, method);
    cells.build(policy);
    inner.update(policy);
    EXPECT_TRUE(inner.search(policy, weight).list_weights.empty());  // not filled
    inner.update(policy, weight);
    EXPECT_EQ(inner.search(policy, weight).list_weights.empty(), !stored);
    EXPECT_TRUE(inner.search(policy, other).list_weights.empty());  // another functor's values
    cells.build(policy);
    inner.update(policy);
    EXPECT_TRUE(inner.search(policy, weight).list_weights.empty());  // filled for the previous lists
    for (int pass = 0; pass < 2; ++pass) {
      if (pass == 1) inner.update(policy, weight);
      DiscreteVariable<std::uint32_t> counts("counts", x.size());
      DiscreteVariable<unsigned> errors("errors", 1);
      particle_for(policy, x.size(),
                   CheckWeights{inner.search(policy, weight), weight, counts.write(policy), errors.read_write(policy)});
      const NeighborSets reference = brute_force(cells.grid(), s.positions, s.positions, true, false);
      const std::vector<std::uint32_t> c = counts.to_vector();
      Index wrong = 0;
      for (Index i = 0; i < x.size(); ++i) wrong += c[i] != reference[i].size();
      EXPECT_EQ(wrong, 0u) << (stored ? "stored" : "direct") << ", pass " << pass;
      EXPECT_EQ(errors.to_vector()[0], 0u) << (stored ? "stored" : "direct") << ", pass " << pass;
    }
  }
}

TYPED_TEST(NeighborRelation, MatchesBruteForce2DFloat) { check_layouts<float, 2>(this->policy); }
TYPED_TEST(NeighborRelation, MatchesBruteForce2DDouble) { check_layouts<double, 2>(this->policy); }
TYPED_TEST(NeighborRelation, MatchesBruteForce3DFloat) { check_layouts<float, 3>(this->policy); }
TYPED_TEST(NeighborRelation, MatchesBruteForce3DDouble) { check_layouts<double, 3>(this->policy); }

// Random particles, a tenth of them beyond the box faces and some with NaN coordinates, with
// the box faces both clamping and flagging them.
template <class T, int D, class P>
void check_outside(P policy, OutsideParticles mode) {
  std::mt19937_64 rng(5);
  std::vector<Vec<T, D>> pos;
  Index nans = 0, outside = 0;
  for (int k = 0; k < 800; ++k) {
    Vec<T, D> p = random_point<T, D>(rng, 0, 1);
    if (k % 10 == 3) {
      p[k % D] = k % 20 == 3 ? T(1) + T(0.05) : -std::numeric_limits<T>::infinity();
      ++outside;
    }
    if (k % 37 == 5) {
      p[(k + 1) % D] = std::numeric_limits<T>::quiet_NaN();
      ++nans;
    }
    pos.push_back(p);
  }
  const Box<T, D> box{Vec<T, D>::constant(T(0)), Vec<T, D>::constant(T(1))};
  DiscreteVariable<Vec<T, D>> x("Position");
  x.assign(pos);
  for (int split : {1, 3}) {
  SCOPED_TRACE("cells of cutoff / " + std::to_string(split));
  CellLinkedList<T, D> cells(x, box, T(0.1), mode, cell_size_for(T(0.1), split));
  cells.build(policy);
  const CellListReport report = cells.report();
  Index outside_or_nan = 0;
  for (const auto& p : pos) outside_or_nan += cells.grid().place(p).status != placement_inside;
  EXPECT_EQ(report.particles, pos.size());
  EXPECT_EQ(report.non_finite, nans);
  EXPECT_EQ(report.out_of_box, outside);
  EXPECT_EQ(report.flagged, mode == OutsideParticles::flag ? outside_or_nan : 0u);
  for (SearchMethod method : {SearchMethod::direct, SearchMethod::stored}) {
    InnerRelation<T, D> inner(cells, method);
    inner.update(policy);
    const NeighborSets expected =
        brute_force(cells.grid(), pos, pos, true, mode == OutsideParticles::flag);
    unsigned errors = 0;
    const NeighborSets got = collect(policy, inner.search(policy), x.size(), capacity_for(expected), errors);
    EXPECT_EQ(errors, 0u);
    EXPECT_TRUE(got == expected) << pair_count(got) << " pairs, expected " << pair_count(expected);
    if (method == SearchMethod::direct) check_cell_ordered_positions(policy, x, cells, expected);
  }
  }
}

TYPED_TEST(NeighborRelation, OutsideAndNaNParticlesClamped) {
  check_outside<float, 3>(this->policy, OutsideParticles::clamp);
  check_outside<double, 2>(this->policy, OutsideParticles::clamp);
}
TYPED_TEST(NeighborRelation, OutsideAndNaNParticlesFlagged) {
  check_outside<double, 3>(this->policy, OutsideParticles::flag);
  check_outside<float, 2>(this->policy, OutsideParticles::flag);
}

// |x_i - x_j|^2 with every product rounded on its own through a volatile, which no compiler
// can fuse into the sum: the reference, independent of the library's uncontracted arithmetic.
template <class T, int D>
T separately_rounded_r2(const Vec<T, D>& xi, const Vec<T, D>& xj) {
  T sum = 0;
  for (int a = 0; a < D; ++a) {
    const T r = xi[a] - xj[a];
    volatile T product = r * r;
    sum = sum + product;
  }
  return sum;
}

// Particles around a centre at almost exactly the cutoff, kept only where a fused r^2 (as nvcc
// or a host with FMA would compute by default) decides differently from the separately
// rounded one. Every policy must decide as the separately rounded r^2.
template <class T, int D, class P>
void check_contraction_sensitive(P policy) {
  const T cutoff = T(0.1);
  const Vec<T, D> centre = Vec<T, D>::constant(T(0.5));
  const SearchGrid<T, D> grid = SearchGrid<T, D>::make({Vec<T, D>{}, Vec<T, D>::constant(T(1))}, cutoff);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0, 1);
  std::vector<Vec<T, D>> pos{centre};
  Index disagreements = 0;
  for (int attempt = 0; attempt < 400000 && pos.size() < 200; ++attempt) {
    Vec<T, D> dir;
    double len2 = 0;
    for (int a = 0; a < D; ++a) dir[a] = static_cast<T>(g(rng)), len2 += double(dir[a]) * dir[a];
    Vec<T, D> x;
    for (int a = 0; a < D; ++a) x[a] = static_cast<T>(centre[a] + dir[a] * cutoff / std::sqrt(len2));
    const T separate = separately_rounded_r2(centre, x);
    T fused = (centre[0] - x[0]) * (centre[0] - x[0]);
    for (int a = 1; a < D; ++a) fused = std::fma(centre[a] - x[a], centre[a] - x[a], fused);
    if ((separate < grid.cutoff_squared) != (fused < grid.cutoff_squared)) {
      pos.push_back(x);
      ++disagreements;
    }
  }
  ASSERT_GT(disagreements, 10u) << "no contraction-sensitive pairs found: the test checks nothing";
  DiscreteVariable<Vec<T, D>> xv("Position");
  xv.assign(pos);
  CellLinkedList<T, D> cells(xv, grid.box, cutoff);
  cells.build(policy);
  InnerRelation<T, D> inner(cells, SearchMethod::direct);
  std::vector<std::uint32_t> expected;
  for (Index j = 1; j < pos.size(); ++j)
    if (separately_rounded_r2(pos[0], pos[j]) < grid.cutoff_squared) expected.push_back(static_cast<std::uint32_t>(j));
  ASSERT_GT(expected.size(), 0u);
  ASSERT_LT(expected.size(), disagreements);
  unsigned errors = 0;
  const NeighborSets got = collect(policy, inner.search(policy), xv.size(), capacity_for({expected}), errors);
  EXPECT_TRUE(got[0] == expected) << got[0].size() << " of the " << disagreements
                                  << " sensitive particles found, expected " << expected.size();
}

TYPED_TEST(NeighborRelation, ContractionSensitivePairsDecidedWithoutFusedMultiplyAdd) {
  check_contraction_sensitive<float, 3>(this->policy);
  check_contraction_sensitive<double, 3>(this->policy);
  check_contraction_sensitive<float, 2>(this->policy);
  check_contraction_sensitive<double, 2>(this->policy);
}

}  // namespace
