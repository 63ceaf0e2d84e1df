#pragma once
// How a relation finds neighbours inside kernels (see neighbor_search.hpp), and the default
// per policy, chosen from the measurements in docs/neighbor_search.md.

#include "unisph/exec/policy.hpp"

namespace unisph {

enum class SearchMethod {
  automatic,  // the faster one measured for the policy (default_search_method)
  direct,     // walk the 3^D cells around x_i on every pass
  stored,     // walk lists of j and of their pair geometry cached by a direct search at update()
};

// The defaults come from the density pass of bench/neighbor (docs/neighbor_search.md), with
// the lists rebuilt whenever the cell list is, i.e. every step in SPH:
//   device: direct search. A stored-list pass is faster than a direct one (H200: 0.54 against
//           0.83 ms per 10^6 particles), but building the lists costs 2.5 ms, so stored lists
//           pay off only beyond ~9 neighbour passes per rebuild; they also take 4 bytes per
//           pair of device memory (3 GB at 10^7 particles).
//   host:   stored lists. On the CPU a stored-list pass is 4-5x faster than a direct one and
//           the build costs about 1.7 direct passes, so from 2-3 neighbour passes per
//           rebuild (density, then forces in every acoustic sub-step) they are faster
//           (measured with uncached CSR lists; the lists now cache each pair's geometry and
//           are built by one search, which favours them more).
// Note the two differ between rebuilds: stored lists keep the geometry of the last update,
// a direct search measures it from the current positions (stored_neighbor_lists.hpp).
template <ExecutionPolicy P>
constexpr SearchMethod default_search_method(P) {
  return P::space == MemorySpace::device ? SearchMethod::direct : SearchMethod::stored;
}

template <ExecutionPolicy P>
constexpr SearchMethod resolve_search_method(SearchMethod method, P policy) {
  return method == SearchMethod::automatic ? default_search_method(policy) : method;
}

}  // namespace unisph
