#pragma once
// StoredNeighborLists<T, D>: the neighbours of every source particle as CSR lists of j
// (offsets per source, 64-bit; 32-bit indices), built with the direct search by
// count -> exclusive scan -> fill. Only j is stored (4 bytes per pair): r_ij is recomputed
// from the current positions when the lists are walked.

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
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    std::uint64_t k = offsets[i];
    search.for_each_direct_neighbor(i, [&](Index j, const NeighborPair<T, D>&) {
      neighbors[k++] = static_cast<std::uint32_t>(j);
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
      : offsets_(name + ".NeighborOffsets"), neighbors_(name + ".Neighbors") {}

  // Lists for sources [0, source_count) from a direct search (its lists, if any, are ignored).
  template <ExecutionPolicy P>
  void build(P policy, NeighborSearch<T, D> direct, Index source_count) {
    direct.list_offsets = {};
    direct.list_neighbors = {};
    offsets_.resize(source_count + 1);
    View<std::uint64_t> offsets = offsets_.write(policy);
    particle_for(policy, source_count, stored_lists_detail::CountNeighbors<T, D>{direct, offsets});
    exclusive_scan(policy, View<const std::uint64_t>(offsets.subview(0, source_count)), offsets);
    // The total is one number: a one-item reduction reads it without copying the offsets.
    const std::uint64_t total = particle_reduce(policy, 1, Sum<std::uint64_t>{},
                                                stored_lists_detail::ReadTotal{offsets});
    neighbors_.resize(0);  // nothing to keep: avoids copying stale pairs on the resize
    neighbors_.resize(static_cast<Index>(total));
    particle_for(policy, source_count,
                 stored_lists_detail::FillNeighbors<T, D>{direct, offsets, neighbors_.write(policy)});
    pair_count_ = static_cast<Index>(total);
  }

  Index pair_count() const { return pair_count_; }
  DiscreteVariable<std::uint64_t>& offsets() { return offsets_; }
  DiscreteVariable<std::uint32_t>& neighbors() { return neighbors_; }

 private:
  DiscreteVariable<std::uint64_t> offsets_;
  DiscreteVariable<std::uint32_t> neighbors_;
  Index pair_count_ = 0;
};

}  // namespace unisph
