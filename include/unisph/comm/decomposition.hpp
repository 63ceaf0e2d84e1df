#pragma once
// Decomposition of a box among the ranks of a communicator.
//
// The box is covered by a uniform grid of cells (CellGrid: at least `min_cell_size` wide,
// the cutoff of the interactions, so that a particle's halo lies in its cell's 3^D
// neighbours); every cell has one owner rank, and a particle belongs to the owner of its cell.
// Two ways to give the cells owners, both balancing a weight per particle (1 by default):
//   morton     the cells in the order of their 64-bit Morton keys (core/morton_key.hpp), cut
//              into `size` consecutive key ranges of about equal weight (split keys; the
//              weights are counted in a global histogram of the keys' leading bits, so a
//              cut lies on a bucket of at most 2^20 buckets);
//   bisection  recursive coordinate bisection: the cell box is split across its longest
//              axis (in cells) at the cell plane that divides the weight in proportion to the
//              ranks on each side, recursively; every rank gets a box of cells.
// Both are collective (every rank passes its own particles) and deterministic: integer
// histograms summed exactly, the same decisions on every rank.
//
// Positions outside the box along a non-periodic axis belong to the edge cells; along a
// periodic axis a position is wrapped into the box first.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "unisph/comm/communicator.hpp"
#include "unisph/core/box.hpp"
#include "unisph/core/config.hpp"
#include "unisph/core/error.hpp"
#include "unisph/core/partition_point.hpp"
#include "unisph/core/morton_key.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/memory/discrete_variable.hpp"

namespace unisph::comm {

template <int D>
struct CellGrid {
  Box<Real, D> box;
  Vec<int, D> cells;         // per axis
  Vec<Real, D> cell_size;    // box extent / cells
  Vec<int, D> periodic;      // 1 where the axis is periodic (period = the box's extent)

  // The cell of x: wrapped along periodic axes, clamped to the edge cells along the others.
  UNISPH_HOST_DEVICE Vec<int, D> cell_of(const Vec<Real, D>& x) const {
    Vec<int, D> c;
    for (int a = 0; a < D; ++a) {
      const Real t = (x[a] - box.lower[a]) / cell_size[a];
      long long i = static_cast<long long>(std::floor(t));
      if (!(t == t)) i = 0;  // NaN: the first cell (the caller's check decides what a NaN position means)
      if (periodic[a]) {
        i %= cells[a];
        if (i < 0) i += cells[a];
      } else {
        i = i < 0 ? 0 : (i >= cells[a] ? cells[a] - 1 : i);
      }
      c[a] = static_cast<int>(i);
    }
    return c;
  }
  UNISPH_HOST_DEVICE Vec<Real, D> period() const { return box.upper - box.lower; }
  std::uint64_t cell_count() const {
    std::uint64_t n = 1;
    for (int a = 0; a < D; ++a) n *= static_cast<std::uint64_t>(cells[a]);
    return n;
  }
};

// The grid of the widest cells no smaller than `min_cell_size` that tile `box`.
template <int D>
CellGrid<D> make_cell_grid(const Box<Real, D>& box, Real min_cell_size, Vec<int, D> periodic = Vec<int, D>{}) {
  if (!(min_cell_size > 0)) throw Error("cell grid: the cell size must be positive, not " + std::to_string(min_cell_size));
  CellGrid<D> g{box, {}, {}, periodic};
  for (int a = 0; a < D; ++a) {
    const Real extent = box.upper[a] - box.lower[a];
    if (!(extent > 0)) throw Error("cell grid: the box " + to_string(box) + " is empty along axis " + std::to_string(a));
    const double n = std::floor(static_cast<double>(extent) / static_cast<double>(min_cell_size));
    if (n > double(1 << 21))
      throw Error("cell grid: " + std::to_string(n) + " cells along axis " + std::to_string(a) +
                  "; Morton keys hold 2^21 cells per axis");
    g.cells[a] = std::max(1, static_cast<int>(n));
    g.cell_size[a] = extent / static_cast<Real>(g.cells[a]);
  }
  return g;
}

enum class DecompositionMethod { morton, bisection };
inline const char* to_string(DecompositionMethod m) { return m == DecompositionMethod::morton ? "morton" : "bisection"; }

// Cells [lower, upper) (upper exclusive) along each axis.
template <int D>
struct CellBox {
  Vec<int, D> lower;
  Vec<int, D> upper;
  UNISPH_HOST_DEVICE bool contains(const Vec<int, D>& c) const {
    for (int a = 0; a < D; ++a)
      if (c[a] < lower[a] || c[a] >= upper[a]) return false;
    return true;
  }
  std::uint64_t cell_count() const {
    std::uint64_t n = 1;
    for (int a = 0; a < D; ++a) n *= static_cast<std::uint64_t>(std::max(0, upper[a] - lower[a]));
    return n;
  }
};

// What kernels hold to find owners (Decomposition::view): the grid, the Morton split keys or
// the bisection boxes, and the interior table where one is kept. Host and device share these
// functions, so a plan built by a kernel makes the same decisions as the host's owner().
template <int D>
struct DecompositionView {
  CellGrid<D> grid;
  int ranks = 1;
  bool morton = true;
  View<const std::uint64_t> splits;    // morton: ranks + 1 keys
  View<const CellBox<D>> boxes;        // bisection: one per rank
  View<const std::uint8_t> interior;   // per cell, row-major with axis 0 fastest; empty: none kept

  UNISPH_HOST_DEVICE int owner_of_cell(const Vec<int, D>& cell) const {
    if (morton) {
      // The number of splits[1 .. ranks - 1] at or below the key (std::upper_bound).
      const std::uint64_t key = morton_key<D>(cell);
      return partition_point(1, ranks, [&](int r) { return splits[Index(r)] <= key; }) - 1;
    }
    for (int r = 0; r < ranks; ++r)
      if (boxes[Index(r)].contains(cell)) return r;
    return -1;  // unreachable: the boxes tile the grid
  }
  UNISPH_HOST_DEVICE int owner(const Vec<Real, D>& x) const { return owner_of_cell(grid.cell_of(x)); }
  // See Decomposition::interior.
  UNISPH_HOST_DEVICE bool is_interior(const Vec<int, D>& cell) const {
    if (interior.empty()) return false;
    std::uint64_t k = 0;
    for (int a = D - 1; a >= 0; --a) k = k * std::uint64_t(grid.cells[a]) + std::uint64_t(cell[a]);
    return interior[Index(k)] != 0;
  }
};

namespace decomposition_detail {
template <int D>
Vec<int, D> cell_of_index(const CellGrid<D>& grid, std::uint64_t k) {
  Vec<int, D> c;
  for (int a = 0; a < D; ++a) {
    c[a] = static_cast<int>(k % std::uint64_t(grid.cells[a]));
    k /= std::uint64_t(grid.cells[a]);
  }
  return c;
}
template <int D>
struct CellOwners {
  DecompositionView<D> decomposition;
  View<std::int32_t> owner;
  void operator()(Index k) const { owner[k] = decomposition.owner_of_cell(cell_of_index<D>(decomposition.grid, k)); }
};
template <int D>
struct InteriorCells {
  CellGrid<D> grid;
  View<const std::int32_t> owner;
  View<std::uint8_t> interior;
  void operator()(Index k) const {
    const Vec<int, D> c = cell_of_index<D>(grid, k);
    int offsets = 1;
    for (int a = 0; a < D; ++a) offsets *= 3;
    for (int o = 0; o < offsets; ++o) {
      std::uint64_t m = 0;
      for (int a = D - 1, code = o; a >= 0; --a) {
        int power = 1;
        for (int b = 0; b < a; ++b) power *= 3;
        const int na = c[a] + (code / power) % 3 - 1;
        if (na < 0 || na >= grid.cells[a]) {
          // Beyond the grid: no neighbour there, except across a periodic face (another cell).
          if (grid.periodic[a]) {
            interior[k] = 0;
            return;
          }
          m = ~std::uint64_t(0);
          break;
        }
        m = m * std::uint64_t(grid.cells[a]) + std::uint64_t(na);
      }
      if (m != ~std::uint64_t(0) && owner[Index(m)] != owner[k]) {
        interior[k] = 0;
        return;
      }
    }
  }
};
}  // namespace decomposition_detail

template <int D>
class Decomposition {
 public:
  const CellGrid<D>& grid() const { return grid_; }
  int ranks() const { return ranks_; }
  DecompositionMethod method() const { return method_; }
  // morton: rank r owns the cells with split[r] <= key < split[r + 1] (ranks() + 1 values).
  std::span<const std::uint64_t> morton_splits() const { return splits_; }
  // bisection: rank r owns boxes()[r].
  std::span<const CellBox<D>> boxes() const { return boxes_; }

  int owner_of_cell(const Vec<int, D>& cell) const { return host_view().owner_of_cell(cell); }
  int owner(const Vec<Real, D>& x) const { return owner_of_cell(grid_.cell_of(x)); }

  // The tables in the memory space of `policy`, for kernels (a plan built on the device).
  template <class P>
  DecompositionView<D> view(P) const {
    return view_in(P::space);
  }

  // True when the cell and its 3^D neighbours have one owner and none lies across a periodic
  // face: a particle there gives no ghost to anyone (the halo's build skips it with this one
  // look-up). False for every cell where the grid has more than 2^26 cells (no table kept).
  bool interior(const Vec<int, D>& cell) const { return host_view().is_interior(cell); }

  static Decomposition from_morton_splits(const CellGrid<D>& grid, std::vector<std::uint64_t> splits) {
    Decomposition d;
    d.grid_ = grid;
    d.method_ = DecompositionMethod::morton;
    d.ranks_ = static_cast<int>(splits.size()) - 1;
    d.splits_ = std::move(splits);
    d.make_tables();
    return d;
  }
  static Decomposition from_boxes(const CellGrid<D>& grid, std::vector<CellBox<D>> boxes) {
    Decomposition d;
    d.grid_ = grid;
    d.method_ = DecompositionMethod::bisection;
    d.ranks_ = static_cast<int>(boxes.size());
    d.boxes_ = std::move(boxes);
    d.make_tables();
    return d;
  }

 private:
  // Host and device copies of the splits, boxes and interior table, shared by the copies of a
  // decomposition (they never change after it is made).
  struct Tables {
    DiscreteVariable<std::uint64_t> splits{"Decomposition.Splits"};
    DiscreteVariable<CellBox<D>> boxes{"Decomposition.Boxes"};
    DiscreteVariable<std::uint8_t> interior{"Decomposition.Interior"};
  };
  DecompositionView<D> host_view() const {
    DecompositionView<D> v;
    v.grid = grid_;
    v.ranks = ranks_;
    v.morton = method_ == DecompositionMethod::morton;
    v.splits = View<const std::uint64_t>(splits_.data(), splits_.size());
    v.boxes = View<const CellBox<D>>(boxes_.data(), boxes_.size());
    v.interior = View<const std::uint8_t>(interior_.data(), interior_.size());
    return v;
  }
  DecompositionView<D> view_in(MemorySpace space) const {
    if (space == MemorySpace::host) return host_view();
    DecompositionView<D> v = host_view();
    v.splits = tables_->splits.read(space);
    v.boxes = tables_->boxes.read(space);
    v.interior = tables_->interior.read(space);
    return v;
  }
  void make_tables() {
    tabulate_interior();
    tables_ = std::make_shared<Tables>();
    tables_->splits.assign(splits_);
    tables_->boxes.assign(boxes_);
    tables_->interior.assign(interior_);
  }
  // interior_[k] = 1 where cell k and all its 3^D neighbours are one rank's (so a particle
  // there sends no ghost: the halo's kernels skip it). Kept up to 2^30 cells (a byte each; a
  // grid of 10^8 cells is a 10^9-particle case's); larger grids check every particle's
  // neighbour cells. Built by host kernels over the cells (par: oneTBB where the build has it).
  void tabulate_interior() {
    const std::uint64_t n = grid_.cell_count();
    if (n > (std::uint64_t(1) << 30)) return;
    std::vector<std::int32_t> owner(n);
    interior_.assign(n, 1);
    const DecompositionView<D> view = host_view();
    particle_for(par, Index(n), decomposition_detail::CellOwners<D>{view, View<std::int32_t>(owner.data(), owner.size())});
    particle_for(par, Index(n),
                 decomposition_detail::InteriorCells<D>{grid_, View<const std::int32_t>(owner.data(), owner.size()),
                                                        View<std::uint8_t>(interior_.data(), interior_.size())});
  }
  CellGrid<D> grid_{};
  DecompositionMethod method_ = DecompositionMethod::morton;
  int ranks_ = 1;
  std::vector<std::uint64_t> splits_;
  std::vector<CellBox<D>> boxes_;
  std::vector<std::uint8_t> interior_;  // per cell, row-major with axis 0 fastest (interior())
  std::shared_ptr<Tables> tables_;
};

namespace decomposition_detail {
// 128-bit products of counts (GCC's and Clang's extension; __extension__ keeps -Wpedantic quiet).
__extension__ typedef unsigned __int128 uint128;
template <int D>
int key_bits(const CellGrid<D>& g) {
  int cells = 1;
  for (int a = 0; a < D; ++a) cells = std::max(cells, g.cells[a]);
  return morton_key_bits(D, cells);
}
inline std::uint64_t weight_of(std::span<const std::uint64_t> weights, std::size_t i) {
  return weights.empty() ? 1 : weights[i];
}
// The index b in [lo, hi] whose prefix (weight before b) is closest to `target` (ties: lower b).
inline std::size_t closest_cut(std::span<const std::uint64_t> prefix, std::size_t lo, std::size_t hi,
                               uint128 target_times_den, std::uint64_t den) {
  std::size_t best = lo;
  uint128 best_err = ~static_cast<uint128>(0);
  for (std::size_t b = lo; b <= hi; ++b) {
    const uint128 v = static_cast<uint128>(prefix[b]) * den;
    const uint128 err = v > target_times_den ? v - target_times_den : target_times_den - v;
    if (err < best_err) {
      best_err = err;
      best = b;
    }
  }
  return best;
}
}  // namespace decomposition_detail

// Morton split keys balancing the weights (collective). `weights` empty: 1 per particle.
template <int D>
Decomposition<D> decompose_morton(const Communicator& comm, const CellGrid<D>& grid,
                                  std::span<const Vec<Real, D>> positions, std::span<const std::uint64_t> weights = {}) {
  using namespace decomposition_detail;
  const int bits = std::max(1, key_bits(grid));
  const int bucket_bits = std::min(bits, 20);
  const int shift = bits - bucket_bits;
  const std::size_t buckets = std::size_t(1) << bucket_bits;
  std::vector<std::uint64_t> histogram(buckets, 0);
  for (std::size_t i = 0; i < positions.size(); ++i)
    histogram[morton_key<D>(grid.cell_of(positions[i])) >> shift] += weight_of(weights, i);
  comm.allreduce_sum(histogram);
  std::vector<std::uint64_t> prefix(buckets + 1, 0);
  for (std::size_t b = 0; b < buckets; ++b) prefix[b + 1] = prefix[b] + histogram[b];
  const std::uint64_t total = prefix[buckets];
  const int p = comm.size();
  std::vector<std::uint64_t> splits(std::size_t(p) + 1);
  splits[0] = 0;
  splits[std::size_t(p)] = ~std::uint64_t(0);
  std::size_t previous = 0;
  for (int r = 1; r < p; ++r) {
    // Cut at the bucket boundary whose prefix is closest to r/p of the total.
    const std::size_t b = closest_cut(prefix, previous, buckets, static_cast<uint128>(total) * r,
                                      static_cast<std::uint64_t>(p));
    splits[std::size_t(r)] = b == buckets ? ~std::uint64_t(0) : static_cast<std::uint64_t>(b) << shift;
    previous = b;
  }
  return Decomposition<D>::from_morton_splits(grid, std::move(splits));
}

// Recursive coordinate bisection of the cell grid balancing the weights (collective).
// Throws when the grid has fewer cells than ranks.
template <int D>
Decomposition<D> decompose_bisection(const Communicator& comm, const CellGrid<D>& grid,
                                     std::span<const Vec<Real, D>> positions,
                                     std::span<const std::uint64_t> weights = {}) {
  using namespace decomposition_detail;
  const int p = comm.size();
  if (grid.cell_count() < std::uint64_t(p))
    throw Error("decomposition: " + std::to_string(p) + " ranks but only " + std::to_string(grid.cell_count()) +
                " cells (cells at least the cutoff wide); use fewer ranks or a larger domain");
  std::vector<Vec<int, D>> cell(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) cell[i] = grid.cell_of(positions[i]);
  std::vector<CellBox<D>> boxes(static_cast<std::size_t>(p));
  CellBox<D> whole{Vec<int, D>{}, grid.cells};
  // Depth first, the same order on every rank: one allreduce per split.
  struct Task {
    int r0, r1;
    CellBox<D> box;
  };
  std::vector<Task> stack{{0, p, whole}};
  while (!stack.empty()) {
    const Task t = stack.back();
    stack.pop_back();
    const int n = t.r1 - t.r0;
    if (n == 1) {
      boxes[std::size_t(t.r0)] = t.box;
      continue;
    }
    int axis = 0;
    for (int a = 1; a < D; ++a)
      if (t.box.upper[a] - t.box.lower[a] > t.box.upper[axis] - t.box.lower[axis]) axis = a;
    const int lo = t.box.lower[axis], hi = t.box.upper[axis];
    const std::uint64_t cross = t.box.cell_count() / std::uint64_t(hi - lo);
    const int n_left = n / 2, n_right = n - n_left;
    // Each side keeps at least as many cells as it has ranks.
    const int s_min = lo + static_cast<int>((std::uint64_t(n_left) + cross - 1) / cross);
    const int s_max = hi - static_cast<int>((std::uint64_t(n_right) + cross - 1) / cross);
    std::vector<std::uint64_t> layers(std::size_t(hi - lo), 0);
    for (std::size_t i = 0; i < cell.size(); ++i)
      if (t.box.contains(cell[i])) layers[std::size_t(cell[i][axis] - lo)] += weight_of(weights, i);
    comm.allreduce_sum(layers);
    std::vector<std::uint64_t> prefix(layers.size() + 1, 0);
    for (std::size_t k = 0; k < layers.size(); ++k) prefix[k + 1] = prefix[k] + layers[k];
    const std::size_t cut = closest_cut(prefix, std::size_t(s_min - lo), std::size_t(s_max - lo),
                                        static_cast<uint128>(prefix.back()) * n_left, std::uint64_t(n));
    const int s = lo + static_cast<int>(cut);
    CellBox<D> left = t.box, right = t.box;
    left.upper[axis] = s;
    right.lower[axis] = s;
    stack.push_back({t.r0 + n_left, t.r1, right});
    stack.push_back({t.r0, t.r0 + n_left, left});
  }
  return Decomposition<D>::from_boxes(grid, std::move(boxes));
}

// Imbalance of a weight spread over the ranks: max / mean (1 is perfect; 0 when the total is 0).
inline double imbalance(const Communicator& comm, std::uint64_t local_weight) {
  const std::uint64_t max = comm.allreduce_max(local_weight);
  const std::uint64_t total = comm.allreduce_sum(local_weight);
  if (total == 0) return 0.0;
  return static_cast<double>(max) * comm.size() / static_cast<double>(total);
}

}  // namespace unisph::comm
