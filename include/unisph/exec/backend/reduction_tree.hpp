#pragma once
// The one association of deterministic_reduce, which every backend executes as it stands here,
// so that a floating-point result has the same bits on seq, par and the GPU and for any number
// of threads (the reference order, also in docs/architecture.md):
//
//   level 0: the items in blocks of `reduction_tree_width` consecutive indices, the last block
//            padded with the identity; each block reduced by the halving tree below;
//   level k: the block results of level k - 1, in block order, reduced the same way;
//   until one value is left (n <= width: the single block's tree; n = 0: the identity).
//
// The halving tree over v[0, width): for s = width/2, width/4, ..., 1: v[t] = op(v[t], v[t + s])
// for t < s; the result is v[0]. It is the shape a GPU block reduces in shared memory with
// coalesced loads, and cheap enough on the host (one extra combine per item).

#include "unisph/core/config.hpp"

namespace unisph::backend {

// Items per leaf block (a power of two; the CUDA backend's threads per block).
inline constexpr Index reduction_tree_width = 256;

// Reduces v[0, reduction_tree_width) in place by the halving tree; returns v[0].
template <class T, class Op>
UNISPH_HOST_DEVICE inline T reduce_halving_tree(T* v, const Op& op) {
  for (Index s = reduction_tree_width / 2; s > 0; s /= 2)
    for (Index t = 0; t < s; ++t) v[t] = op(v[t], v[t + s]);
  return v[0];
}

// Blocks of the level above a level of `count` values.
UNISPH_HOST_DEVICE inline Index reduction_tree_blocks(Index count) {
  return (count + reduction_tree_width - 1) / reduction_tree_width;
}

}  // namespace unisph::backend
