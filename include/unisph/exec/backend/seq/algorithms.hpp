#pragma once
// The sequential backend: plain loops on the calling thread. It is the reference the other
// backends are tested against and the easy one to debug.

#include "unisph/exec/backend/host/radix_sort.hpp"
#include "unisph/exec/backend/host/tree_reduce.hpp"
#include "unisph/exec/backend/backend.hpp"

namespace unisph::backend {

template <>
struct Backend<SequencedPolicy> {
  template <class F>
  static void particle_for(Index n, const F& f) {
    for (Index i = 0; i < n; ++i) f(i);
  }

  template <class T, class Op, class F>
  static T particle_reduce(Index n, T identity, const Op& op, const F& f) {
    T acc = identity;
    for (Index i = 0; i < n; ++i) acc = op(acc, f(i));
    return acc;
  }

  // The fixed association of reduction_tree.hpp (the same bits as par and the GPU).
  template <class T, class Op, class F>
  static T deterministic_reduce(Index n, T identity, const Op& op, const F& f) {
    return host::tree_reduce(n, identity, op, f, [](Index count, const auto& body) {
      for (Index b = 0; b < count; ++b) body(b);
    });
  }

  // out may alias in; out has n or n + 1 elements (the total in out[n]).
  template <class T>
  static void exclusive_scan(const T* in, T* out, Index n, bool with_total) {
    T running{};
    for (Index i = 0; i < n; ++i) {
      const T value = in[i];
      out[i] = running;
      running = running + value;
    }
    if (with_total) out[n] = running;
  }

  template <class K, class V>
  static void sort_pairs(K* keys, V* values, Index n, int begin_bit, int end_bit) {
    host::radix_sort_pairs(keys, values, n, begin_bit, end_bit, host::SerialChunks{});
  }
};

}  // namespace unisph::backend
