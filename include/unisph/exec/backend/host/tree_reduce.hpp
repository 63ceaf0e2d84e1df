#pragma once
// deterministic_reduce on the host, shared by the seq and par backends: the association of
// reduction_tree.hpp, level by level; only how a level's blocks are run differs (a loop, or
// oneTBB's threads: each block is reduced by one thread in the tree's order, so the result does
// not depend on which thread takes which block).

#include <vector>

#include "unisph/exec/backend/reduction_tree.hpp"

namespace unisph::backend::host {

// for_blocks(count, body) calls body(b) once for every b in [0, count), in any order.
template <class T, class Op, class F, class ForBlocks>
T tree_reduce(Index n, T identity, const Op& op, const F& f, const ForBlocks& for_blocks) {
  if (n == 0) return identity;
  constexpr Index width = reduction_tree_width;
  std::vector<T> level(reduction_tree_blocks(n));
  for_blocks(Index(level.size()), [&](Index b) {
    const F local = f;  // a private copy of the kernel's views, as on the device
    T v[width];
    const Index begin = b * width;
    for (Index t = 0; t < width; ++t) v[t] = begin + t < n ? local(begin + t) : identity;
    level[b] = reduce_halving_tree(v, op);
  });
  while (level.size() > 1) {
    std::vector<T> next(reduction_tree_blocks(Index(level.size())));
    for_blocks(Index(next.size()), [&](Index b) {
      T v[width];
      const Index begin = b * width;
      for (Index t = 0; t < width; ++t) v[t] = begin + t < Index(level.size()) ? level[begin + t] : identity;
      next[b] = reduce_halving_tree(v, op);
    });
    level.swap(next);
  }
  return level[0];
}

}  // namespace unisph::backend::host
