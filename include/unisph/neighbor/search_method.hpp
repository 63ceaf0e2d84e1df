#pragma once
// How a relation finds neighbours inside kernels (see neighbor_search.hpp), and the default
// per policy, chosen from the measurements in docs/neighbor_search.md.

#include "unisph/exec/policy.hpp"

namespace unisph {

enum class SearchMethod {
  automatic,  // the faster one measured for the policy (default_search_method)
  direct,     // walk the 3^D cells around x_i on every pass
  stored,     // walk CSR lists of j built by a direct search at update()
};

// Device: direct search (stored lists cost 4 bytes per pair of device memory, and their
// build is itself a direct search). Host: direct search as well. Both measured on the density
// pass of bench/neighbor (docs/neighbor_search.md has the figures and the reasoning).
template <ExecutionPolicy P>
constexpr SearchMethod default_search_method(P) {
  return SearchMethod::direct;
}

template <ExecutionPolicy P>
constexpr SearchMethod resolve_search_method(SearchMethod method, P policy) {
  return method == SearchMethod::automatic ? default_search_method(policy) : method;
}

}  // namespace unisph
