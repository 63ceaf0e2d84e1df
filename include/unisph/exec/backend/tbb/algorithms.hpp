#pragma once
// The oneTBB backend: the host's cores. Reductions use parallel_deterministic_reduce with a
// grain that depends on n only, so a floating-point sum is the same from run to run and for
// any number of threads.

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_scan.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include "unisph/exec/backend/backend.hpp"
#include "unisph/exec/backend/host/radix_sort.hpp"
#include "unisph/exec/backend/host/tree_reduce.hpp"

namespace unisph::backend {

namespace tbb_detail {
// Items per task: large enough that scheduling costs nothing next to the loop body.
inline constexpr Index for_grain = 2048;
inline Index reduce_grain(Index n) { return std::max<Index>(4096, n / 512); }

struct ParallelChunks {
  Index chunk_count(Index n) const {
    const Index threads = static_cast<Index>(tbb::this_task_arena::max_concurrency());
    return std::clamp<Index>(n / 65536, 1, 4 * threads);
  }
  template <class F>
  void run(Index chunks, const F& f) const {
    tbb::parallel_for(Index(0), chunks, [&](Index c) { f(c); });
  }
};
}  // namespace tbb_detail

template <>
struct Backend<ParallelPolicy> {
  template <class F>
  static void particle_for(Index n, const F& f) {
    if (n == 0) return;
    tbb::parallel_for(tbb::blocked_range<Index>(0, n, tbb_detail::for_grain), [&](const tbb::blocked_range<Index>& r) {
      const F local = f;  // a private copy of the kernel's views, as on the device
      for (Index i = r.begin(); i != r.end(); ++i) local(i);
    });
  }

  template <class T, class Op, class F>
  static T particle_reduce(Index n, T identity, const Op& op, const F& f) {
    return tbb::parallel_deterministic_reduce(
        tbb::blocked_range<Index>(0, n, tbb_detail::reduce_grain(n)), identity,
        [&](const tbb::blocked_range<Index>& r, T acc) {
          const F local = f;
          for (Index i = r.begin(); i != r.end(); ++i) acc = op(acc, local(i));
          return acc;
        },
        [&](const T& a, const T& b) { return op(a, b); });
  }

  // The fixed association of reduction_tree.hpp: each block is reduced by one task in the tree's
  // order, so the result has seq's bits for any number of threads.
  template <class T, class Op, class F>
  static T deterministic_reduce(Index n, T identity, const Op& op, const F& f) {
    return host::tree_reduce(n, identity, op, f, [](Index count, const auto& body) {
      tbb::parallel_for(tbb::blocked_range<Index>(0, count, 8), [&](const tbb::blocked_range<Index>& r) {
        for (Index b = r.begin(); b != r.end(); ++b) body(b);
      });
    });
  }

  template <class T>
  static void exclusive_scan(const T* in, T* out, Index n, bool with_total) {
    const T total = tbb::parallel_scan(
        tbb::blocked_range<Index>(0, n, 16384), T{},
        [&](const tbb::blocked_range<Index>& r, T running, bool is_final) {
          for (Index i = r.begin(); i != r.end(); ++i) {
            const T value = in[i];  // read before the write: in and out may be the same array
            if (is_final) out[i] = running;
            running = running + value;
          }
          return running;
        },
        [](const T& a, const T& b) { return a + b; });
    if (with_total) out[n] = total;
  }

  template <class K, class V>
  static void sort_pairs(K* keys, V* values, Index n, int begin_bit, int end_bit) {
    host::radix_sort_pairs(keys, values, n, begin_bit, end_bit, tbb_detail::ParallelChunks{});
  }
};

}  // namespace unisph::backend
