#pragma once
// StoredNeighborLists<T, D>: the neighbours of every source particle as CSR lists (offsets per
// source, 64-bit) of j (32-bit) and of the pair's geometry (NeighborPair: r_ij, |r_ij|^2,
// |r_ij|), built with the direct search by count -> exclusive scan -> fill.
//
// The geometry is cached: a pass over the lists reads it instead of the neighbours' positions
// (no gather, no subtraction, no square root), and it is that of the configuration at the
// build — the lists are a snapshot of the particle configuration, to be rebuilt when the
// particles have moved enough to matter (in SPH: every advection step). Memory per pair:
// 4 + (D + 2) sizeof(T) bytes (36 in 2D double, 24 in 3D float).

#include <cstdint>

#include "unisph/exec/algorithms.hpp"
#include "unisph/memory/discrete_variable.hpp"
#include "unisph/neighbor/neighbor_search.hpp"

namespace unisph {

namespace stored_lists_detail {

template <class T, int D>
struct CountNeighbors {
  NeighborSearch<T, D> search;
  View<std::uint64_t> counts;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    std::uint64_t n = 0;
    search.for_each_direct_neighbor(i, [&](Index, const NeighborPair<T, D>&) { ++n; });
    counts[i] = n;
  }
};

template <class T, int D>
struct FillNeighbors {
  NeighborSearch<T, D> search;
  View<const std::uint64_t> offsets;
  View<std::uint32_t> neighbors;
  View<NeighborPair<T, D>> pairs;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    std::uint64_t k = offsets[i];
    search.for_each_direct_neighbor(i, [&](Index j, const NeighborPair<T, D>& pair) {
      neighbors[k] = static_cast<std::uint32_t>(j);
      pairs[k] = pair;
      ++k;
    });
  }
};

struct ReadTotal {
  View<const std::uint64_t> offsets;
  UNISPH_HOST_DEVICE std::uint64_t operator()(Index) const { return offsets[offsets.size() - 1]; }
};

}  // namespace stored_lists_detail

template <class T, int D>
class StoredNeighborLists {
 public:
  explicit StoredNeighborLists(const std::string& name)
      : offsets_(name + ".NeighborOffsets"), neighbors_(name + ".Neighbors"), pairs_(name + ".NeighborPairs") {}

  // Lists for sources [0, source_count) from a direct search (its lists, if any, are ignored).
  template <ExecutionPolicy P>
  void build(P policy, NeighborSearch<T, D> direct, Index source_count) {
    direct.list_offsets = {};
    direct.list_neighbors = {};
    direct.list_pairs = {};
    offsets_.resize(source_count + 1);
    View<std::uint64_t> offsets = offsets_.write(policy);
    particle_for(policy, source_count, stored_lists_detail::CountNeighbors<T, D>{direct, offsets});
    exclusive_scan(policy, View<const std::uint64_t>(offsets.subview(0, source_count)), offsets);
    // The total is one number: a one-item reduction reads it without copying the offsets.
    const std::uint64_t total = particle_reduce(policy, 1, Sum<std::uint64_t>{},
                                                stored_lists_detail::ReadTotal{offsets});
    // Only grow: a list that shrinks keeps its allocation (the kernels that view it are then
    // not rebuilt either), and nothing is copied on a resize.
    if (neighbors_.size() < static_cast<Index>(total)) {
      neighbors_.resize(0);
      neighbors_.resize(static_cast<Index>(total));
      pairs_.resize(0);
      pairs_.resize(static_cast<Index>(total));
    }
    particle_for(policy, source_count,
                 stored_lists_detail::FillNeighbors<T, D>{direct, offsets, neighbors_.write(policy), pairs_.write(policy)});
    pair_count_ = static_cast<Index>(total);
  }

  Index pair_count() const { return pair_count_; }
  DiscreteVariable<std::uint64_t>& offsets() { return offsets_; }
  DiscreteVariable<std::uint32_t>& neighbors() { return neighbors_; }
  DiscreteVariable<NeighborPair<T, D>>& pairs() { return pairs_; }

 private:
  DiscreteVariable<std::uint64_t> offsets_;
  DiscreteVariable<std::uint32_t> neighbors_;
  DiscreteVariable<NeighborPair<T, D>> pairs_;
  Index pair_count_ = 0;
};

}  // namespace unisph
