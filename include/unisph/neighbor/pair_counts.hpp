#pragma once
// Per-particle pair counts of a neighbour search, as kernels for particle_reduce (named functors:
// device code cannot take host lambdas). Benchmarks report candidate and neighbour pairs per
// second with them:
//   particle_reduce(policy, n, Sum<std::uint64_t>{}, CandidateCount<T, D>{search})
#include <cstdint>

#include "unisph/core/config.hpp"
#include "unisph/neighbor/neighbor_search.hpp"

namespace unisph {

// The particles a direct search of i looks at.
template <class T, int D>
struct CandidateCount {
  NeighborSearch<T, D> search;
  UNISPH_HOST_DEVICE std::uint64_t operator()(Index i) const { return search.candidate_count(i); }
};

// The neighbours of i within the cutoff, found by a direct search.
template <class T, int D>
struct NeighborCount {
  NeighborSearch<T, D> search;
  UNISPH_HOST_DEVICE std::uint64_t operator()(Index i) const {
    std::uint64_t n = 0;
    search.for_each_direct_neighbor(i, [&](Index, const NeighborPair<T, D>&) { ++n; });
    return n;
  }
};

}  // namespace unisph
