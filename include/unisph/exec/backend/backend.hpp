#pragma once
// Backend<Policy> is specialised once per backend folder (seq/, tbb/, cuda/); the front end in
// unisph/exec/algorithms.hpp only forwards to it. A backend provides, for n items:
//   particle_for(n, f)                           f(i) for every i
//   particle_reduce(n, identity, op, f) -> T     op-combination of f(i)
//   deterministic_reduce(n, identity, op, f) -> T  the same in the association of reduction_tree.hpp
//   exclusive_scan(in, out, n, with_total)
//   sort_pairs(keys, values, n, begin_bit, end_bit)

#include "unisph/core/config.hpp"
#include "unisph/exec/policy.hpp"

namespace unisph::backend {

template <class Policy>
struct Backend;

template <class...>
inline constexpr bool dependent_false_v = false;

}  // namespace unisph::backend
