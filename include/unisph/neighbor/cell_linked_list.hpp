#pragma once
// CellLinkedList<T, D>: particles grouped by cell in CSR form — offsets[c] .. offsets[c + 1]
// are the positions in `particles` of the indices of the particles in cell c — built by
//   count (one atomic per particle, on the device one per warp and cell: atomic_increment_shared;
//          it also gives the particle its slot in the cell)
//   -> exclusive scan of the counts into offsets
//   -> fill (each particle writes its index to offsets[cell] + slot)
// with the same kernels on every policy. The slot comes from the counting atomic, so the
// fill needs no second atomic; the order inside a cell is the order in which the atomics
// happened (the sets are the same on every policy, the order within a cell may differ).
//
// When the particles are already in cell order (each particle's cell index >= the previous
// one's, e.g. after ParticleSorter with SortOrder::cell_index), the particles of cell c are
// exactly the indices offsets[c] .. offsets[c + 1]: the build detects it (one more pass, no
// host wait) and the direct search then reads positions contiguously, without the indirection
// through `particles`, in ascending j (a deterministic order).
//
// Ordered by id (order_within_cells_by_id(set)): each cell lists its particles in ascending
// global id (the set's "ParticleId"), whoever owns them and wherever they sit in the arrays
// (ghosts carry their owner's id), so that every neighbour sum has one order on any number of
// ranks and on every policy. `particles` is then a stable radix sort (sort_pairs, CUB on the
// device) of the keys (bucket << id_bits) | (id - first_id) with the particle indices as values;
// the counts and the scan give the offsets as before, and the counting atomics give no slots.
// The list is then "in cell order" (the direct search's contiguous path) only where `particles`
// is the identity, i.e. the keys ascend with the index (ParticleSorter with
// SortOrder::cell_index_then_id): the same order either way. A pass first checks whether the
// keys ascend (the pass that tells cell order) and writes the identity; only where they do not
// (ghosts among the particles, or no sort since the particles moved) are the keys stored and
// sorted, which on the device costs one wait for the flag. An id outside the set's range (a
// slot nobody wrote) sorts after the cell's others, by index.
//
// On several ranks (keep_owned_view(set)) the build also gives a view of the owned particles
// alone, the set's first owned_count(), where they are sorted by (cell, id): offsets over them
// only, in cell order (owned_view). A particle whose neighbours are all owned (an interior one,
// comm/interior_split.hpp) then walks each row of cells as one contiguous range, as on one
// rank, instead of the id-ordered list's runs with their two index loads per row (measured on
// four H200s: the relaxations 17 to 23 % slower per rank than one GPU on as many particles).
// Its table covers only the block of cells that holds the owned particles (SearchGrid::sub_grid,
// found by a reduction at each build; periodic axes whole): about the rank's share of the domain,
// where a table over every cell would add 4 bytes per cell of the whole domain to every rank
// (about 9 bytes per particle in the 10^9-particle run on four GPUs). It costs a second count per
// owned particle, the reduction (one wait for its result) and a scan per build.
//
// On request (store_positions_in_cell_order) the build also writes a copy of the positions in
// the list's order, padded to 16 bytes in 3D float (CellPoint), for particles that are not in
// cell order (e.g. in Morton order): a search that visits its sources in the list's order
// (NeighborSearch::cell_order_source) then reads each row of cells as one contiguous range with
// one aligned load per candidate, as it does for particles in cell order. The copy holds the
// positions of the build: a search through it measures r_ij at that configuration (as stored
// lists do), which is what a pass that follows the build at once, or a dual-time-stepping step,
// wants. It costs a bucket-ordered write per particle in the build and sizeof(CellPoint) bytes
// per particle (16 in 3D float, 32 in 3D double, 8 and 16 in 2D).
//
// Positions outside the box or with a NaN coordinate are never undefined behaviour: they are
// counted (report()) and, as the caller chooses, either clamped into the border cell
// (OutsideParticles::clamp: still found as neighbours where within the cutoff) or put in a
// separate bucket after the last cell (OutsideParticles::flag: they neither find nor are
// found as neighbours). A NaN coordinate never passes the cutoff test, wherever it is put.

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <limits>
#include <string>

#include "unisph/core/partition_point.hpp"
#include "unisph/dynamics/kernel_context.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/atomic.hpp"
#include "unisph/exec/workspace.hpp"
#include "unisph/memory/discrete_variable.hpp"
#include "unisph/neighbor/search_grid.hpp"
#include "unisph/particles/particle_set.hpp"

namespace unisph {

enum class OutsideParticles { clamp, flag };

// What the last build saw. out_of_box and non_finite count particles (one with both a NaN and
// an out-of-box coordinate counts in both); flagged is the size of the separate bucket.
struct CellListReport {
  Index particles = 0;
  Index out_of_box = 0;
  Index non_finite = 0;
  Index flagged = 0;
  bool in_cell_order = false;  // the particles were in cell order (ordered by id: and by id in each cell)
};

// A position as the cell-ordered copy holds it: the D coordinates padded to a power-of-two
// number of components, aligned to its size, so that the device fetches it with one vector
// load (two in 3D double).
template <class T, int D>
struct alignas(sizeof(T) * (D == 3 ? 4 : D)) CellPoint {
  static_assert(D == 2 || D == 3, "CellPoint is the padded position of a 2D or 3D search grid.");
  static constexpr int padded = D == 3 ? 4 : D;
  T v[padded];
  UNISPH_HOST_DEVICE static CellPoint of(const Vec<T, D>& x) {
    CellPoint p{};
    for (int a = 0; a < D; ++a) p.v[a] = x[a];
    return p;
  }
  UNISPH_HOST_DEVICE Vec<T, D> position() const {
    Vec<T, D> x;
    for (int a = 0; a < D; ++a) x[a] = v[a];
    return x;
  }
};

// What kernels hold: the grid and read-only views of the CSR arrays.
template <class T, int D>
struct CellListView {
  SearchGrid<T, D> grid;
  bool flag_outside;
  View<const Vec<T, D>> positions;
  View<const std::uint32_t> offsets;    // cell_count() + 2: the cells, the flagged bucket, the end
  View<const std::uint32_t> particles;  // particle indices grouped by cell
  View<const unsigned long long> counters;  // [3] != 0: the particles are not in cell order
  // The positions at the build in the order of `particles` (empty unless asked for, and not
  // written when the particles are in cell order: see the header comment).
  View<const CellPoint<T, D>> points;
  // Ordered by id (empty otherwise): for each place k, the end of the run of places from k on
  // whose particles are consecutive indices (particles[k + m] == particles[k] + m). A loop over a
  // row walks each run without the index list: the owned particles of a run on several ranks,
  // sorted by (cell, id), are one run per row wherever no ghost lies between them.
  View<const std::uint32_t> run_end;

  UNISPH_HOST_DEVICE Index flagged_bucket() const { return offsets.size() - 2; }
  // True when the particles of cell c are exactly the indices offsets[c] .. offsets[c + 1]
  // (for a list ordered by id: `particles` is the identity, so the ids ascend within each cell).
  UNISPH_HOST_DEVICE bool in_cell_order() const { return counters[3] == 0; }
};

namespace cell_list_detail {

struct ZeroCounts {
  View<std::uint32_t> counts;
  View<unsigned long long> counters;
  View<std::uint32_t> owned_counts;  // the owned view's (empty without one)
  UNISPH_HOST_DEVICE void operator()(Index c) const {
    if (c < counts.size()) counts[c] = 0;
    if (c < counters.size()) counters[c] = 0;
    if (c < owned_counts.size()) owned_counts[c] = 0;
  }
};

// A finite coordinate (or an infinity) beyond a face of `box`, as SearchGrid::place() tells it.
template <class T, int D>
UNISPH_HOST_DEVICE bool outside_of(const Box<T, D>& box, const Vec<T, D>& x) {
  for (int a = 0; a < D; ++a)
    if (x[a] < box.lower[a] || x[a] > box.upper[a]) return true;
  return false;
}

// The bucket of a particle placed at p: its cell, or the flagged bucket for one outside the box
// (or not finite) where the list flags them.
template <class T, int D>
UNISPH_HOST_DEVICE std::uint32_t bucket_of_placement(const SearchGrid<T, D>& grid, const CellPlacement<D>& p,
                                                     bool flag_outside, std::uint32_t flagged_bucket) {
  if (p.status != placement_inside && flag_outside) return flagged_bucket;
  return static_cast<std::uint32_t>(grid.linear_index(p.cell));
}

template <class T, int D>
struct CountParticles {
  SearchGrid<T, D> grid;
  bool flag_outside;
  std::uint32_t flagged_bucket;
  View<const Vec<T, D>> positions;
  View<std::uint32_t> bucket_of;
  View<std::uint32_t> slot_of;  // empty when the list is ordered by id (the sort places them)
  View<std::uint32_t> counts;
  View<unsigned long long> counters;  // out of box, non-finite, flagged, not in cell order
  Index reported;  // out of box and non-finite are counted among particles [0, reported)
  // Out of box means out of this box where report_box_set (CellLinkedList::report_outside_of),
  // else out of the grid's.
  Box<T, D> report_box;
  bool report_box_set;
  View<std::uint32_t> owned_counts;  // the owned view's: particles [0, owned) counted again,
  Index owned;                       // in the cells of owned_grid (their block of grid's)
  SearchGrid<T, D> owned_grid;

  UNISPH_HOST_DEVICE void operator()(Index i) const {
    const Vec<T, D> x = positions[i];
    const CellPlacement<D> p = grid.place(x);
    const std::uint32_t bucket = bucket_of_placement(grid, p, flag_outside, flagged_bucket);
    if (p.status != placement_inside) {
      if ((p.status & placement_non_finite) && i < reported) atomic_add(&counters[1], 1ull);
      if (flag_outside) atomic_add(&counters[2], 1ull);
    }
    if (i < reported && (report_box_set ? outside_of(report_box, x) : (p.status & placement_out_of_box) != 0))
      atomic_add(&counters[0], 1ull);
    bucket_of[i] = bucket;
    const std::uint32_t slot = atomic_increment_shared(&counts[bucket]);
    if (!slot_of.empty()) slot_of[i] = slot;
    if (i < owned)
      atomic_increment_shared(&owned_counts[bucket_of_placement(owned_grid, owned_grid.place(x), flag_outside,
                                                                static_cast<std::uint32_t>(owned_grid.cell_count()))]);
  }
};

// Sets a flag that many threads may set at once. A plain store of the same value, not an
// atomic read-modify-write: in a random order half the particles set it, and atomics on one
// address would serialise them (measured: 10x slower builds on the H200). Plain stores to one
// address serialise too (H100: the order check of 10^7 particles in Morton order with cells of
// cutoff / 2 took 162 us, and still 169 us with one store per warp), so on the device one lane
// per warp stores, and only while its cached read of the flag still says 0 (a stale 0 costs
// one more store, never a wrong result).
UNISPH_HOST_DEVICE inline void raise_flag_if(bool condition, unsigned long long* flag) {
#if UNISPH_DEVICE_CODE
  const unsigned raising = __ballot_sync(__activemask(), condition);
  unsigned lane;
  asm("mov.u32 %0, %%laneid;" : "=r"(lane));
  if (raising != 0 && lane == static_cast<unsigned>(__ffs(raising)) - 1u &&
      *static_cast<const unsigned long long*>(flag) == 0)
    *static_cast<volatile unsigned long long*>(flag) = 1;
#else
  if (condition) std::atomic_ref<unsigned long long>(*flag).store(1, std::memory_order_relaxed);
#endif
}

// The block of cells from `first` to `last` (inclusive): the owned view's (CellLinkedList),
// joined over the owned particles' cells by a reduction.
template <int D>
struct CellRange {
  Vec<int, D> first;
  Vec<int, D> last;
  static CellRange empty() {
    return {Vec<int, D>::constant(std::numeric_limits<int>::max()), Vec<int, D>::constant(std::numeric_limits<int>::min())};
  }
};
template <int D>
struct JoinCellRanges {
  UNISPH_HOST_DEVICE CellRange<D> operator()(const CellRange<D>& a, const CellRange<D>& b) const {
    return {unisph::min(a.first, b.first), unisph::max(a.last, b.last)};
  }
};
template <class T, int D>
struct CellOfParticle {
  SearchGrid<T, D> grid;
  View<const Vec<T, D>> positions;
  UNISPH_HOST_DEVICE CellRange<D> operator()(Index i) const {
    const Vec<int, D> c = grid.place(positions[i]).cell;
    return {c, c};
  }
};

// Sets counters[3] when some particle's bucket is below its predecessor's.
struct CheckCellOrder {
  View<const std::uint32_t> bucket_of;
  View<unsigned long long> counters;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    raise_flag_if(bucket_of[i + 1] < bucket_of[i], &counters[3]);
  }
};

// Ordered by id: particle i's sort key, (bucket << id_bits) | (id - first_id), an id outside
// [first_id, first_id + id_count) as id_count (after the cell's others; the sort is stable).
struct IdKey {
  View<const std::uint32_t> bucket_of;
  View<const std::uint64_t> ids;
  std::uint64_t first_id;
  std::uint64_t id_count;
  int id_bits;
  UNISPH_HOST_DEVICE std::uint64_t operator()(Index i) const {
    const std::uint64_t id = ids[i] - first_id;  // below first_id: wraps to a large value
    return (std::uint64_t(bucket_of[i]) << id_bits) | (id < id_count ? id : id_count);
  }
};

// Ordered by id: `particles` as the identity, and counters[3] set where some key is below its
// predecessor's (the stable sort of the keys is then not the identity); counters[4] where that
// happens among the first `owned` (the owned view then does not hold).
struct IdentityWhereKeysAscend {
  IdKey key;
  View<std::uint32_t> particles;
  View<unsigned long long> counters;
  Index owned;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    particles[i] = static_cast<std::uint32_t>(i);
    if (i + 1 < particles.size()) {
      const bool descends = key(i + 1) < key(i);
      raise_flag_if(descends, &counters[3]);
      if (i + 1 < owned) raise_flag_if(descends, &counters[4]);
    }
  }
};

// Ordered by id, where the keys do not ascend: each particle's key for the sort, which carries
// the identity written before into `particles`.
struct IdKeys {
  IdKey key;
  View<std::uint64_t> keys;
  UNISPH_HOST_DEVICE void operator()(Index i) const { keys[i] = key(i); }
};

// Ordered by id, where the owned particles' keys ascend and only the ghosts' do not: the ghosts'
// keys and indices, to be sorted apart (a few per cent of the particles) and merged with the
// owned ones (PlaceOwned, PlaceGhosts) instead of a radix sort of every key.
struct GhostKeys {
  IdKey key;
  Index owned;
  View<std::uint64_t> keys;
  View<std::uint32_t> index;
  UNISPH_HOST_DEVICE void operator()(Index k) const {
    keys[k] = key(owned + k);
    index[k] = static_cast<std::uint32_t>(owned + k);
  }
};
// The merge places each particle where the stable sort of all keys puts it: an owned particle
// after the ghosts whose keys are smaller, a ghost after the owned particles whose keys are
// smaller or equal (equal keys, ids outside the set's range, keep the order of the indices, and
// every owned index is below every ghost's). Binary searches: no atomics, the same places on
// every policy.
struct PlaceOwned {
  IdKey key;
  View<const std::uint64_t> ghost_keys;  // sorted
  View<std::uint32_t> particles;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    const std::uint64_t k = key(i);
    const Index before = partition_point(Index(0), ghost_keys.size(), [&](Index g) { return ghost_keys[g] < k; });
    particles[i + before] = static_cast<std::uint32_t>(i);
  }
};
struct PlaceGhosts {
  IdKey key;
  Index owned;
  View<const std::uint64_t> ghost_keys;  // sorted
  View<const std::uint32_t> ghost_index;  // the ghosts' indices in that order
  View<std::uint32_t> particles;
  UNISPH_HOST_DEVICE void operator()(Index k) const {
    const std::uint64_t g = ghost_keys[k];
    const Index before = partition_point(Index(0), owned, [&](Index i) { return key(i) <= g; });
    particles[k + before] = ghost_index[k];
  }
};

// Ordered by id: the runs of consecutive particle indices in `particles` (see
// CellListView::run_end). starts[k] = 1 where a run begins at place k.
struct RunStarts {
  View<const std::uint32_t> particles;
  View<std::uint32_t> starts;
  UNISPH_HOST_DEVICE void operator()(Index k) const {
    starts[k] = k == 0 || particles[k] != particles[k - 1] + 1 ? 1u : 0u;
  }
};
// first[r]: the place where run r begins (first[runs] = the place count); before[k]: the
// exclusive scan of starts (the number of runs that begin before place k).
struct RunBegins {
  View<const std::uint32_t> starts;
  View<const std::uint32_t> before;
  View<std::uint32_t> first;
  UNISPH_HOST_DEVICE void operator()(Index k) const {
    if (starts[k]) first[before[k]] = static_cast<std::uint32_t>(k);
    if (k + 1 == starts.size()) first[before[k] + starts[k]] = static_cast<std::uint32_t>(k + 1);
  }
};
struct RunEnds {
  View<const std::uint32_t> starts;
  View<const std::uint32_t> before;
  View<const std::uint32_t> first;
  View<std::uint32_t> run_end;
  UNISPH_HOST_DEVICE void operator()(Index k) const { run_end[k] = first[before[k] + starts[k]]; }
};

struct FillCells {
  View<const std::uint32_t> bucket_of;
  View<const std::uint32_t> slot_of;
  View<const std::uint32_t> offsets;
  View<std::uint32_t> particles;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    particles[offsets[bucket_of[i]] + slot_of[i]] = static_cast<std::uint32_t>(i);
  }
};

// Sets changed[0] where particle i would now fall in another bucket than the one it was binned
// in (the bucket CountParticles gives it), or its position is not finite (which the next build
// reports).
template <class T, int D>
struct CheckBuckets {
  SearchGrid<T, D> grid;
  bool flag_outside;
  std::uint32_t flagged_bucket;
  View<const Vec<T, D>> positions;
  View<const std::uint32_t> bucket_of;
  View<unsigned long long> changed;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    const CellPlacement<D> p = grid.place(positions[i]);
    const std::uint32_t bucket = bucket_of_placement(grid, p, flag_outside, flagged_bucket);
    raise_flag_if(bucket != bucket_of[i] || (p.status & placement_non_finite), &changed[0]);
  }
};

// The positions copied into the list's order, unless the particles are already in cell order
// (counters[3] == 0: set by CheckCellOrder, which ran before). A gather after the fill: the
// writes are contiguous and the reads follow the particles of each cell (measured on an H100
// against writing the copy from the fill, a scatter of 16-byte elements: see
// docs/neighbor_search.md).
template <class T, int D>
struct CopyPointsInCellOrder {
  View<const std::uint32_t> particles;
  View<const Vec<T, D>> positions;
  View<const unsigned long long> counters;
  View<CellPoint<T, D>> points;
  UNISPH_HOST_DEVICE void operator()(Index k) const {
    if (counters[3] != 0) points[k] = CellPoint<T, D>::of(positions[particles[k]]);
  }
};

}  // namespace cell_list_detail

template <class T, int D>
class CellLinkedList {
 public:
  using Position = Vec<T, D>;

  // A list over `positions` (all of them: owned particles and ghosts) in `box`, for
  // neighbours closer than `cutoff`, with cells of `cell_size` (0: the cutoff; down to
  // cutoff / 4, which the search walks with a wider stencil: see search_grid.hpp).
  CellLinkedList(DiscreteVariable<Position>& positions, const Box<T, D>& box, T cutoff,
                 OutsideParticles outside = OutsideParticles::clamp, T cell_size = T(0))
      : CellLinkedList(positions, SearchGrid<T, D>::make(box, cutoff, cell_size), outside) {}

  // A list over `positions` on a grid made beforehand (SearchGrid::make_periodic: cells that
  // divide the periodic axes exactly, for wrapped cell indices; see periodic_cell_list.hpp).
  CellLinkedList(DiscreteVariable<Position>& positions, const SearchGrid<T, D>& grid,
                 OutsideParticles outside = OutsideParticles::clamp)
      : positions_(positions),
        grid_(grid),
        outside_(outside),
        offsets_(positions.name() + ".CellOffsets", grid_.cell_count() + 2),
        particles_(positions.name() + ".CellParticles"),
        bucket_of_(positions.name() + ".CellOfParticle"),
        slot_of_(positions.name() + ".SlotInCell"),
        counters_(positions.name() + ".CellListCounters", 5),
        points_(positions.name() + ".CellOrderedPositions"),
        keys_(positions.name() + ".CellSortKeys") {}

  // Lists each cell's particles in ascending id (`set`'s "ParticleId", which must have one
  // element per position: the set whose positions these are) from the next build on (see the
  // header comment). Costs a radix sort of 64-bit keys per build (docs/neighbor_search.md).
  void order_within_cells_by_id(ParticleSet& set) { id_set_ = &set; }
  bool orders_within_cells_by_id() const { return id_set_ != nullptr; }

  // Also give the view of `set`'s owned particles alone (see the header comment) from the next
  // build on; `set` is the one whose ids order the list (order_within_cells_by_id).
  void keep_owned_view(const ParticleSet& set) { owned_set_ = &set; }
  // Ordered by id, where the owned particles' keys ascend: whether a build sorts only the
  // ghosts' keys and merges them with the owned ones (the default) or sorts every key, as
  // before the merge (the same list; kept to measure the one against the other).
  void sort_only_ghosts(bool on) { sort_only_ghosts_ = on; }
  // Whether the last build gave the owned view: the list is ordered by id and the owned
  // particles were sorted by (cell, id) (known at the build's end: on the device, the build
  // waits for its order flags).
  bool owned_view_ready() const { return owned_ready_; }

  // Also keep a copy of the positions in the list's order at each build (see the header
  // comment); takes effect at the next build.
  void store_positions_in_cell_order(bool store = true) {
    store_points_ = store;
    if (!store) points_.resize(0);
  }
  bool stores_positions_in_cell_order() const { return store_points_; }

  const SearchGrid<T, D>& grid() const { return grid_; }
  OutsideParticles outside_particles() const { return outside_; }
  Index cell_count() const { return grid_.cell_count(); }
  DiscreteVariable<Position>& positions() { return positions_; }
  // The CSR arrays (for tests and for code that walks cells itself).
  DiscreteVariable<std::uint32_t>& offsets() { return offsets_; }
  DiscreteVariable<std::uint32_t>& particles() { return particles_; }
  DiscreteVariable<std::uint32_t>& bucket_of_particle() { return bucket_of_; }

  // Rebuilds the list from the current positions. Asynchronous on the device.
  template <ExecutionPolicy P>
  void build(P policy) {
    const Index n = positions_.size();
    if (n >= Index(std::numeric_limits<std::uint32_t>::max()))
      throw Error("CellLinkedList: " + std::to_string(n) + " particles in " + positions_.describe() +
                  "; cell lists index particles with 32 bits");
    const bool by_id = id_set_ != nullptr;
    if (by_id && id_set_->ids().size() != n)
      throw Error("CellLinkedList over " + positions_.describe() + ": ordered by the ids of particle set '" +
                  id_set_->name() + "', which holds " + std::to_string(id_set_->ids().size()) + " particles");
    const bool owned_view = by_id && owned_set_ != nullptr;
    const Index owned = owned_view ? std::min(owned_set_->owned_count(), n) : 0;
    // Where the owned particles' keys ascend, a build sorts only the ghosts' (sort_by_id): any
    // ascending first part would do; the owned view's flag needs its own set's.
    const Index sorted_owned = owned_view ? owned : by_id ? std::min(id_set_->owned_count(), n) : 0;
    owned_ready_ = false;
    if (owned_view) owned_grid_ = owned_block(policy, owned);
    particles_.resize(n);
    bucket_of_.resize(n);
    slot_of_.resize(by_id ? 0 : n);
    owned_offsets_.resize(owned_view ? owned_grid_.cell_count() + 2 : 0);
    // Ordered by id: the sort keys and the runs' helper arrays live only within the build.
    WorkspaceScope scope(policy);
    const Index buckets = grid_.cell_count() + 1;
    View<std::uint32_t> offsets = offsets_.write(policy);
    View<unsigned long long> counters = counters_.write(policy);
    const View<std::uint32_t> owned_offsets = owned_view ? owned_offsets_.write(policy) : View<std::uint32_t>{};
    particle_for(policy, std::max<Index>(buckets + 1, counters.size()),
                 cell_list_detail::ZeroCounts{offsets, counters, owned_offsets});
    particle_for(policy, n,
                 cell_list_detail::CountParticles<T, D>{grid_, outside_ == OutsideParticles::flag,
                                                        static_cast<std::uint32_t>(grid_.cell_count()),
                                                        positions_.read(policy), bucket_of_.write(policy),
                                                        by_id ? View<std::uint32_t>{} : slot_of_.write(policy),
                                                        offsets, counters, reported_, report_box_, report_box_set_,
                                                        owned_offsets, owned, owned_grid_});
    if (by_id) {
      if (sort_by_id(policy, scope, n, sorted_owned, counters)) find_runs(policy, scope, n);
      else run_end_.resize(0);
    } else if (n > 1) {
      particle_for(policy, n - 1, cell_list_detail::CheckCellOrder{bucket_of_.read(policy), counters});
    }
    exclusive_scan(policy, View<const std::uint32_t>(offsets.subview(0, buckets)), offsets);
    if (owned_ready_)
      exclusive_scan(policy, View<const std::uint32_t>(owned_offsets.subview(0, owned_grid_.cell_count() + 1)),
                     owned_offsets);
    if (!by_id)
      particle_for(policy, n,
                   cell_list_detail::FillCells{bucket_of_.read(policy), slot_of_.read(policy), offsets,
                                               particles_.write(policy)});
    if (store_points_) {
      points_.resize(n);
      particle_for(policy, n,
                   cell_list_detail::CopyPointsInCellOrder<T, D>{particles_.read(policy), positions_.read(policy),
                                                                 counters, points_.write(policy)});
    }
    built_count_ = n;
    ++builds_;
  }

  // After the positions moved, with the particles and their order as at the last build: true
  // where every particle is still in the bucket it was binned in, so that the lists stand as
  // they are (a build would give the same ones) and only the cell-ordered copy of the
  // positions, where kept, is refreshed; false where a build must follow. Waits for the check
  // on the device (one flag). Moving walls re-bin this way: a paddle's particles cross a cell
  // face in a few advection steps of a hundred, and a build sorts every wall particle.
  template <ExecutionPolicy P>
  bool keep_if_cells_unchanged(P policy) {
    const Index n = positions_.size();
    if (builds_ == 0 || n != built_count_) return false;
    changed_.resize(1);
    View<unsigned long long> changed = changed_.write(policy);
    particle_for(policy, 1, cell_list_detail::ZeroCounts{{}, changed, {}});
    particle_for(policy, n,
                 cell_list_detail::CheckBuckets<T, D>{grid_, outside_ == OutsideParticles::flag,
                                                      static_cast<std::uint32_t>(grid_.cell_count()),
                                                      positions_.read(policy), bucket_of_.read(policy), changed});
    if (changed_.read(MemorySpace::host)[0] != 0) return false;
    if (store_points_)
      particle_for(policy, n,
                   cell_list_detail::CopyPointsInCellOrder<T, D>{particles_.read(policy), positions_.read(policy),
                                                                 counters_.read(policy), points_.write(policy)});
    return true;
  }

  // How many times build() ran: relations compare it to tell stale stored lists.
  std::uint64_t builds() const { return builds_; }

  // report() counts the particles out of the box or not finite among the first n only (all
  // where never called): a set whose ghosts lie outside by design (other ranks' periodic
  // images, clamped into the border cells) reports its owned particles.
  void report_only_first(Index n) { reported_ = n; }
  // report() counts as out of the box the particles outside `box` instead of those outside the
  // grid's: a grid that covers only the region the particles occupy (the rare one beyond is
  // clamped into a border cell, and still found) still reports those that left a larger domain.
  void report_outside_of(const Box<T, D>& box) {
    report_box_ = box;
    report_box_set_ = true;
  }

  // The counts of the last build (waits for it on the device; copies four numbers).
  CellListReport report() {
    View<const unsigned long long> c = counters_.read(MemorySpace::host);
    return {built_count_, static_cast<Index>(c[0]), static_cast<Index>(c[1]), static_cast<Index>(c[2]), c[3] == 0};
  }

  // The kernel-side view in a policy's memory space (the list must have been built there or
  // will be copied there).
  template <ExecutionPolicy P>
  CellListView<T, D> view(P) {
    return {grid_, outside_ == OutsideParticles::flag, positions_.read(P::space), offsets_.read(P::space),
            particles_.read(P::space), counters_.read(P::space),
            store_points_ ? points_.read(P::space) : View<const CellPoint<T, D>>{},
            run_end_.size() ? run_end_.read(P::space) : View<const std::uint32_t>{}};
  }
  // The owned particles alone, in cell order (keep_owned_view; only where owned_view_ready()).
  // Their indices are the list's, so a kernel reads its views as before; its counters' [3] is the
  // owned particles' order flag (0: in cell order).
  template <ExecutionPolicy P>
  CellListView<T, D> owned_view(P) {
    if (!owned_ready_) throw Error("CellLinkedList over " + positions_.describe() + ": no owned view was built");
    return {owned_grid_, outside_ == OutsideParticles::flag, positions_.read(P::space), owned_offsets_.read(P::space),
            particles_.read(P::space), counters_.read(P::space).subview(1, 4), View<const CellPoint<T, D>>{},
            View<const std::uint32_t>{}};
  }
  // The same through a kernel shell's context, which records the variables it views.
  CellListView<T, D> view(KernelContext& context) {
    return {grid_, outside_ == OutsideParticles::flag, context.read(positions_), context.read(offsets_),
            context.read(particles_), context.read(counters_),
            store_points_ ? context.read(points_) : View<const CellPoint<T, D>>{},
            run_end_.size() ? context.read(run_end_) : View<const std::uint32_t>{}};
  }

 private:
  // The block of cells that holds the first `owned` particles (the owned view's grid).
  template <ExecutionPolicy P>
  SearchGrid<T, D> owned_block(P policy, Index owned) const {
    if (owned == 0) return grid_.sub_grid(Vec<int, D>{}, Vec<int, D>{});
    const cell_list_detail::CellRange<D> r =
        particle_reduce(policy, owned, cell_list_detail::CellRange<D>::empty(), cell_list_detail::JoinCellRanges<D>{},
                        cell_list_detail::CellOfParticle<T, D>{grid_, positions_.read(policy)});
    return grid_.sub_grid(r.first, r.last);
  }

  // Ordered by id: run_end for every place (see CellListView::run_end), where the sort was not
  // the identity (sort_by_id). Three passes and a scan of the places.
  template <ExecutionPolicy P>
  void find_runs(P policy, WorkspaceScope& scope, Index n) {
    run_end_.resize(n);
    View<const std::uint32_t> particles = particles_.read(policy);
    const View<std::uint32_t> starts = scope.take(policy, run_starts_, n);
    particle_for(policy, n, cell_list_detail::RunStarts{particles, starts});
    const View<std::uint32_t> before = scope.take(policy, run_before_, n + 1);
    exclusive_scan(policy, View<const std::uint32_t>(starts), before);
    const View<std::uint32_t> first = scope.take(policy, run_first_, n + 1);  // at most n runs, and the end
    particle_for(policy, n, cell_list_detail::RunBegins{starts, before, first});
    particle_for(policy, n, cell_list_detail::RunEnds{starts, before, first, run_end_.write(policy)});
  }

  // `particles` as the stable sort of the (bucket, id) keys (see the header comment);
  // counters[3] set where the keys do not ascend with the index, counters[4] where they do not
  // among the set's owned particles (the first `owned`). Returns false where they do:
  // `particles` is then the identity, and no key is stored or sorted. One pass checks the order
  // and writes the identity, and the flag is read at once (on the device a wait for 8 bytes):
  // particles sorted by (cell, id) just before (ParticleSorter, SortOrder::cell_index_then_id)
  // with no ghost among them, a run on one GPU, thus skip the radix sort of 64-bit keys and the
  // runs' four index arrays (24 bytes per particle, and a few per cent of an H100's step).
  // Where only the ghosts break the order (several ranks, the owned particles sorted by (cell,
  // id) at the step's end), the ghosts' keys alone are sorted and merged with the owned ones by
  // binary searches: the same `particles` as the sort of every key, for a radix sort of the
  // ghosts (a few per cent of the keys) and its scratch.
  template <ExecutionPolicy P>
  bool sort_by_id(P policy, WorkspaceScope& scope, Index n, Index owned, View<unsigned long long> counters) {
    ParticleSet& set = *id_set_;
    const std::uint64_t id_count = set.id_count();
    int id_bits = 0;
    while (id_bits < 64 && (std::uint64_t(1) << id_bits) <= id_count) ++id_bits;  // id_count itself fits
    int bucket_bits = 0;
    while ((std::uint64_t(1) << bucket_bits) <= std::uint64_t(grid_.cell_count())) ++bucket_bits;
    if (bucket_bits + id_bits > 64)
      throw Error("CellLinkedList over " + positions_.describe() + ": " + std::to_string(grid_.cell_count()) +
                  " cells and " + std::to_string(id_count) + " ids of particle set '" + set.name() +
                  "' need " + std::to_string(bucket_bits + id_bits) + " key bits; ordering by id sorts 64");
    const cell_list_detail::IdKey key{bucket_of_.read(policy), set.ids().read(policy), set.first_id(), id_count, id_bits};
    View<std::uint32_t> particles = particles_.write(policy);
    particle_for(policy, n, cell_list_detail::IdentityWhereKeysAscend{key, particles, counters, owned});
    const View<const unsigned long long> flags = counters_.read(MemorySpace::host);
    const bool owned_ascend = n < 2 || flags[4] == 0;
    owned_ready_ = owned_set_ != nullptr && owned_ascend;
    if (n < 2 || flags[3] == 0) return false;
    if (sort_only_ghosts_ && owned_ascend && owned < n) {
      const Index ghosts = n - owned;
      const View<std::uint64_t> ghost_keys = scope.take(policy, keys_, ghosts);
      const View<std::uint32_t> ghost_index = scope.take(policy, ghost_index_, ghosts);
      particle_for(policy, ghosts, cell_list_detail::GhostKeys{key, owned, ghost_keys, ghost_index});
      sort_pairs(policy, ghost_keys, ghost_index, 0, bucket_bits + id_bits);
      particle_for(policy, owned, cell_list_detail::PlaceOwned{key, ghost_keys, particles});
      particle_for(policy, ghosts, cell_list_detail::PlaceGhosts{key, owned, ghost_keys, ghost_index, particles});
      return true;
    }
    const View<std::uint64_t> keys = scope.take(policy, keys_, n);
    particle_for(policy, n, cell_list_detail::IdKeys{key, keys});
    sort_pairs(policy, keys, particles, 0, bucket_bits + id_bits);
    return true;
  }

  DiscreteVariable<Position>& positions_;
  SearchGrid<T, D> grid_;
  OutsideParticles outside_;
  DiscreteVariable<std::uint32_t> offsets_;
  DiscreteVariable<std::uint32_t> particles_;
  DiscreteVariable<std::uint32_t> bucket_of_;
  DiscreteVariable<std::uint32_t> slot_of_;
  DiscreteVariable<unsigned long long> counters_;
  DiscreteVariable<CellPoint<T, D>> points_;
  DiscreteVariable<std::uint64_t> keys_;  // ordered by id: the sort keys (the host's storage; WorkspaceScope)
  DiscreteVariable<unsigned long long> changed_{"CellList.BucketChanged"};  // keep_if_cells_unchanged
  DiscreteVariable<std::uint32_t> ghost_index_{"CellList.GhostOrder"};  // sort_by_id's merge (WorkspaceScope)
  DiscreteVariable<std::uint32_t> run_end_{"CellList.RunEnd"};  // ordered by id (find_runs)
  DiscreteVariable<std::uint32_t> run_starts_{"CellList.RunStarts"};  // these three: the host's storage (WorkspaceScope)
  DiscreteVariable<std::uint32_t> run_before_{"CellList.RunsBefore"};
  DiscreteVariable<std::uint32_t> run_first_{"CellList.RunFirst"};
  ParticleSet* id_set_ = nullptr;         // ordered by the ids of this set; null: by the atomics
  const ParticleSet* owned_set_ = nullptr;  // keep_owned_view
  DiscreteVariable<std::uint32_t> owned_offsets_{"CellList.OwnedOffsets"};
  SearchGrid<T, D> owned_grid_{};  // the owned view's: the block of grid_'s cells holding them
  bool owned_ready_ = false;
  bool sort_only_ghosts_ = true;
  bool store_points_ = false;
  Index built_count_ = 0;
  Index reported_ = std::numeric_limits<Index>::max();  // report_only_first()
  Box<T, D> report_box_{};  // report_outside_of()
  bool report_box_set_ = false;
  std::uint64_t builds_ = 0;
};

}  // namespace unisph
