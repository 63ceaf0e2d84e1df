#pragma once
// StoredNeighborLists<T, D>: the neighbours of every source particle i, as a count per source
// and a fixed number of slots per source (the capacity), each slot holding j (32-bit) and the
// pair's geometry (NeighborPair: r_ij, |r_ij|^2, |r_ij|, e_ij).
//
// The geometry is cached: a pass over the lists reads it instead of the neighbours' positions
// (no gather, no subtraction, no square root, no division), and it is that of the configuration at the
// build — the lists are a snapshot of the particle configuration, to be rebuilt when the
// particles have moved enough to matter (in SPH: every advection step).
//
// Why fixed slots rather than CSR (count -> scan -> fill): the build is then a single direct
// search that writes each pair once and counts the neighbours, with no second search and no
// scan; CSR needs the search twice (measured on the 2D dam break, seq: the two searches of the
// CSR build took 25 % of the run). The capacity is the largest count seen so far (plus an
// eighth after it grows): a build that finds a source with more neighbours than the capacity
// grows it and searches again. Memory: capacity x sources x (4 + (2 D + 2) sizeof(T)) bytes
// (52 per slot in 2D double, 36 in 3D float).
//
// Slot k of source i lies at i * source_stride + k * slot_stride: source after source on the
// host (each particle's pairs are contiguous for one thread), slot after slot on the device
// (the threads of a warp, neighbouring i, read neighbouring addresses).

#include <cstdint>
#include <cstring>
#include <type_traits>
#include <typeindex>
#include <typeinfo>
#include <vector>

#include "unisph/exec/algorithms.hpp"
#include "unisph/memory/discrete_variable.hpp"
#include "unisph/neighbor/neighbor_search.hpp"

#if !UNISPH_DEVICE_CODE && defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace unisph {

namespace stored_lists_detail {

// Searches the neighbours of i, writes the first `capacity` of them into i's slots and its
// full count into counts[i] (a count above the capacity tells the build to grow and retry).
template <class T, int D>
struct FillSlots {
  NeighborSearch<T, D> search;
  View<std::uint32_t> counts;
  View<std::uint32_t> neighbors;
  View<NeighborPair<T, D>> pairs;
  std::uint64_t capacity, source_stride, slot_stride;
  UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void operator()(Index i) const {
    std::uint64_t n = 0;
    const std::uint64_t base = i * source_stride;
#if UNISPH_DEVICE_CODE
    search.for_each_direct_neighbor(i, [&](Index j, const NeighborPair<T, D>& pair) {
      if (n < capacity) {
        const std::uint64_t slot = base + n * slot_stride;
        neighbors[slot] = static_cast<std::uint32_t>(j);
        pairs[slot] = pair;
      }
      ++n;
    });
#else
    // Host: the cutoff test accepts about a third of the candidates at random, so branching
    // on it mispredicts, and the square root and division of each accepted pair then wait on
    // each other. Instead every candidate is written into the next free slot and only an
    // accepted one advances it (no unpredictable branch); the accepted pairs are completed
    // afterwards in a loop whose iterations are independent. Same pairs, same order, same bits.
    // (Measured on the 2D dam break at H/40, seq, 0 <= t <= 3: the whole run 3.4 -> 3.3 s.)
    // The whole walk is inlined here (UNISPH_NEIGHBOR_LOOP) and reads local copies of the
    // search, the views and the sizes, so that n, the pointers and the cutoff stay in registers
    // (as a separate function, GCC kept n in memory: a store-to-load chain per candidate).
    // Measured on the 2D dam break, seq, t = 0..3: 2.55 -> 2.47 s CPU (flattening alone).
    const NeighborSearch<T, D> walk = search;
    const View<std::uint32_t> slot_neighbors = neighbors;
    const View<NeighborPair<T, D>> slot_pairs = pairs;
    const std::uint64_t slot_capacity = capacity, stride = slot_stride;
    walk.for_each_direct_candidate(i, [&](Index j, const Vec<T, D>& xi, const Vec<T, D>& xj) {
      Vec<T, D> r_ij;
      T r2;
      const bool accepted = walk.targets.grid.test_pair(xi, xj, r_ij, r2);
      if (n < slot_capacity) {
        const std::uint64_t slot = base + n * stride;
        slot_neighbors[slot] = static_cast<std::uint32_t>(j);
        slot_pairs[slot].r_ij = r_ij;
        slot_pairs[slot].squared_distance = r2;
      }
      n += accepted ? 1u : 0u;
    });
    const std::uint64_t filled = n < capacity ? n : capacity;
    complete_slots(base, filled);
#endif
    counts[i] = static_cast<std::uint32_t>(n);
  }

#if !UNISPH_DEVICE_CODE
  // NeighborPair::complete() for the slots [0, filled) of the source at `base`. In double with
  // SSE2, two pairs at a time: the square roots and the divisions 1 / |r_ij| of two pairs in one
  // packed instruction each (they are what the completion waits on; the packed ones give the
  // same correctly rounded bits, and e_ij is r_ij * (1 / |r_ij|) as in complete()).
  // Measured on the 2D dam break, seq: the completion was about half of the build's own time.
  void complete_slots(std::uint64_t base, std::uint64_t filled) const {
    std::uint64_t k = 0;
#if defined(__SSE2__)
    if constexpr (std::is_same_v<T, double>) {
      for (; k + 1 < filled; k += 2) {
        NeighborPair<T, D>& a = pairs[base + k * slot_stride];
        NeighborPair<T, D>& b = pairs[base + (k + 1) * slot_stride];
        const __m128d r = _mm_sqrt_pd(_mm_set_pd(b.squared_distance, a.squared_distance));
        const __m128d inverse = _mm_div_pd(_mm_set1_pd(1.0), r);
        alignas(16) double rs[2], inverses[2];
        _mm_store_pd(rs, r);
        _mm_store_pd(inverses, inverse);
        a.r = rs[0];
        b.r = rs[1];
        a.e_ij = rs[0] > 0.0 ? a.r_ij * inverses[0] : Vec<T, D>{};
        b.e_ij = rs[1] > 0.0 ? b.r_ij * inverses[1] : Vec<T, D>{};
      }
    }
#endif
    for (; k < filled; ++k) pairs[base + k * slot_stride].complete();
  }
#endif
};

// weights[slot] = weight(pairs[slot]) for the filled slots of i.
template <class T, int D, class W>
struct FillWeights {
  View<const std::uint32_t> counts;
  View<const NeighborPair<T, D>> pairs;
  View<T> weights;
  W weight;
  std::uint64_t source_stride, slot_stride;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    const std::uint64_t n = counts[i];
    std::uint64_t slot = i * source_stride;
    for (std::uint64_t k = 0; k < n; ++k, slot += slot_stride) weights[slot] = weight(pairs[slot]);
  }
};

struct CountSummary {
  std::uint64_t total;
  std::uint64_t largest;
};
struct CombineCounts {
  UNISPH_HOST_DEVICE CountSummary operator()(const CountSummary& a, const CountSummary& b) const {
    return {a.total + b.total, a.largest < b.largest ? b.largest : a.largest};
  }
};
struct SummariseCounts {
  View<const std::uint32_t> counts;
  UNISPH_HOST_DEVICE CountSummary operator()(Index i) const { return {counts[i], counts[i]}; }
};

}  // namespace stored_lists_detail

template <class T, int D>
class StoredNeighborLists {
 public:
  explicit StoredNeighborLists(const std::string& name)
      : counts_(name + ".NeighborCounts"),
        neighbors_(name + ".Neighbors"),
        pairs_(name + ".NeighborPairs"),
        weights_(name + ".PairWeights") {}

  // Lists for sources [0, source_count) from a direct search (its lists, if any, are ignored).
  template <ExecutionPolicy P>
  void build(P policy, NeighborSearch<T, D> direct, Index source_count) {
    direct.list_counts = {};
    direct.list_neighbors = {};
    direct.list_pairs = {};
    counts_.resize(source_count);
    space_ = P::space;
    source_count_ = source_count;
    ++builds_;
    for (;;) {
      const std::uint64_t slots = std::uint64_t(source_count) * capacity_;
      // Reallocated only when the layout changes (capacity or source count; rare once the
      // capacity settled): kernels that hold the strides are then rebuilt with the new ones.
      if (capacity_ != laid_out_capacity_ || source_count != laid_out_sources_) {
        neighbors_.resize(0);  // nothing to keep: no copy on the resize
        neighbors_.resize(static_cast<Index>(slots));
        pairs_.resize(0);
        pairs_.resize(static_cast<Index>(slots));
        laid_out_capacity_ = capacity_;
        laid_out_sources_ = source_count;
      }
      const Layout layout = layout_for(P::space, source_count);
      particle_for(policy, source_count,
                   stored_lists_detail::FillSlots<T, D>{direct, counts_.write(policy), neighbors_.write(policy),
                                                        pairs_.write(policy), capacity_, layout.source_stride,
                                                        layout.slot_stride});
      const stored_lists_detail::CountSummary summary =
          particle_reduce(policy, source_count, stored_lists_detail::CountSummary{0, 0},
                          stored_lists_detail::CombineCounts{},
                          stored_lists_detail::SummariseCounts{counts_.read(policy)});
      pair_count_ = static_cast<Index>(summary.total);
      if (summary.largest <= capacity_) break;
      capacity_ = summary.largest + summary.largest / 8;  // room to grow a little before the next retry
    }
  }

  // An optional column of one value per pair, weight(pair), in the slots' layout, for the
  // lists of the last build (NeighborSearch::for_each_weighted_neighbor reads it). W is a
  // trivially copyable functor; which one filled the column is remembered (type and bytes), so
  // a search asks for it with the same functor and gets it only if it is current.
  template <ExecutionPolicy P, class W>
  void fill_weights(P policy, const W& weight) {
    static_assert(std::is_trivially_copyable_v<W>, "The pair weight functor is copied into a kernel.");
    if (weights_.size() != neighbors_.size()) {
      weights_.resize(0);
      weights_.resize(neighbors_.size());
    }
    const Layout layout = layout_for(P::space, source_count_);
    particle_for(policy, source_count_,
                 stored_lists_detail::FillWeights<T, D, W>{counts_.read(policy), pairs_.read(policy),
                                                           weights_.write(policy), weight, layout.source_stride,
                                                           layout.slot_stride});
    weights_from_build_ = builds_;
    weight_type_ = std::type_index(typeid(W));
    weight_bytes_.assign(reinterpret_cast<const unsigned char*>(&weight),
                         reinterpret_cast<const unsigned char*>(&weight) + sizeof(W));
  }
  // Whether the weight column holds weight(pair) for the pairs of the last build.
  template <class W>
  bool has_weights_of(const W& weight) const {
    return weights_from_build_ == builds_ && weight_type_ == std::type_index(typeid(W)) &&
           weight_bytes_.size() == sizeof(W) && std::memcmp(weight_bytes_.data(), &weight, sizeof(W)) == 0;
  }
  DiscreteVariable<T>& weights() { return weights_; }

  Index pair_count() const { return pair_count_; }
  Index source_count() const { return source_count_; }
  std::uint64_t capacity() const { return capacity_; }
  // Where slot k of source i is, for lists read in `space` (the space of the last build).
  std::uint64_t slot(Index i, std::uint64_t k) const {
    const Layout layout = layout_for(space_, source_count_);
    return i * layout.source_stride + k * layout.slot_stride;
  }
  std::uint64_t source_stride(MemorySpace space) const { return layout_for(space, source_count_).source_stride; }
  std::uint64_t slot_stride(MemorySpace space) const { return layout_for(space, source_count_).slot_stride; }
  // The space whose layout the lists have (they must be read in it; the relations check this).
  MemorySpace built_in() const { return space_; }

  DiscreteVariable<std::uint32_t>& counts() { return counts_; }
  DiscreteVariable<std::uint32_t>& neighbors() { return neighbors_; }
  DiscreteVariable<NeighborPair<T, D>>& pairs() { return pairs_; }

 private:
  struct Layout {
    std::uint64_t source_stride, slot_stride;
  };
  Layout layout_for(MemorySpace space, Index source_count) const {
    if (space == MemorySpace::device) return {1, std::uint64_t(source_count)};
    return {capacity_, 1};
  }

  DiscreteVariable<std::uint32_t> counts_;
  DiscreteVariable<std::uint32_t> neighbors_;
  DiscreteVariable<NeighborPair<T, D>> pairs_;
  DiscreteVariable<T> weights_;
  std::uint64_t builds_ = 0;
  std::uint64_t weights_from_build_ = ~std::uint64_t(0);
  std::type_index weight_type_ = std::type_index(typeid(void));
  std::vector<unsigned char> weight_bytes_;
  std::uint64_t capacity_ = 0;
  std::uint64_t laid_out_capacity_ = ~std::uint64_t(0);  // the layout the arrays were last allocated for
  Index laid_out_sources_ = 0;
  MemorySpace space_ = MemorySpace::host;
  Index source_count_ = 0;
  Index pair_count_ = 0;
};

}  // namespace unisph
