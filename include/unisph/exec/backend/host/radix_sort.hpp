#pragma once
// Stable LSD radix sort of (key, value) pairs on the host, 8 bits per pass, shared by the
// seq and par backends. The pass structure (histogram per chunk -> offsets -> scatter per
// chunk) is the same for both; only how the chunks are run differs. Passes whose digit is
// the same for every key are skipped, so presorted-equal keys cost one histogram per pass.

#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "unisph/core/config.hpp"

namespace unisph::backend::host {

struct SerialChunks {
  Index chunk_count(Index) const { return 1; }
  template <class F>
  void run(Index chunks, const F& f) const {
    for (Index c = 0; c < chunks; ++c) f(c);
  }
};

template <class K, class V, class Chunks>
void radix_sort_pairs(K* keys, V* values, Index n, int begin_bit, int end_bit, const Chunks& chunks) {
  if (n < 2 || begin_bit >= end_bit) return;
  constexpr int digit_bits = 8;
  constexpr int radix = 1 << digit_bits;
  const Index chunk_count = chunks.chunk_count(n);
  const Index chunk_size = (n + chunk_count - 1) / chunk_count;

  std::unique_ptr<K[]> key_buffer(new K[n]);
  std::unique_ptr<V[]> value_buffer(new V[n]);
  K* key_src = keys;
  V* value_src = values;
  K* key_dst = key_buffer.get();
  V* value_dst = value_buffer.get();
  std::vector<std::array<Index, radix>> counts(chunk_count);

  for (int shift = begin_bit; shift < end_bit; shift += digit_bits) {
    const int bits = end_bit - shift < digit_bits ? end_bit - shift : digit_bits;
    const K mask = static_cast<K>((K(1) << bits) - 1);
    chunks.run(chunk_count, [&](Index c) {
      auto& count = counts[c];
      count.fill(0);
      const Index end = (c + 1) * chunk_size < n ? (c + 1) * chunk_size : n;
      for (Index i = c * chunk_size; i < end; ++i) ++count[(key_src[i] >> shift) & mask];
    });
    // Offsets digit-major, chunk-minor, which keeps the sort stable.
    Index running = 0;
    bool trivial = false;
    for (int d = 0; d < radix; ++d) {
      Index digit_total = 0;
      for (Index c = 0; c < chunk_count; ++c) digit_total += counts[c][d];
      if (digit_total == n) trivial = true;
      for (Index c = 0; c < chunk_count; ++c) {
        const Index here = counts[c][d];
        counts[c][d] = running;
        running += here;
      }
    }
    if (trivial) continue;  // every key has the same digit: this pass would copy only
    chunks.run(chunk_count, [&](Index c) {
      auto& offset = counts[c];
      const Index end = (c + 1) * chunk_size < n ? (c + 1) * chunk_size : n;
      for (Index i = c * chunk_size; i < end; ++i) {
        const Index to = offset[(key_src[i] >> shift) & mask]++;
        key_dst[to] = key_src[i];
        value_dst[to] = value_src[i];
      }
    });
    std::swap(key_src, key_dst);
    std::swap(value_src, value_dst);
  }
  if (key_src != keys) {
    std::memcpy(keys, key_src, n * sizeof(K));
    std::memcpy(values, value_src, n * sizeof(V));
  }
}

}  // namespace unisph::backend::host
