#pragma once
// Reordering an array of any element type by a permutation, on every policy:
//   dst[k] = src[permutation[k]]   for k < count
// It works on the bytes of the elements (in 4-byte words where the size allows), so one
// compiled kernel serves every variable type of a registry.

#include <cstdint>

#include "unisph/exec/algorithms.hpp"

namespace unisph {

namespace permute_detail {

template <class Word>
struct GatherElements {
  View<const std::uint32_t> permutation;
  const Word* src;
  Word* dst;
  Index words;  // per element
  UNISPH_HOST_DEVICE void operator()(Index k) const {
    const Word* from = src + static_cast<Index>(permutation[k]) * words;
    Word* to = dst + k * words;
    for (Index w = 0; w < words; ++w) to[w] = from[w];
  }
};

template <class Word>
struct CopyWords {
  const Word* src;
  Word* dst;
  UNISPH_HOST_DEVICE void operator()(Index k) const { dst[k] = src[k]; }
};

}  // namespace permute_detail

// Gathers `count` elements of `element_size` bytes from `src` into `dst` (distinct arrays in
// the policy's memory space) in the order of `permutation`.
template <ExecutionPolicy P>
void gather_by_permutation(P policy, View<const std::uint32_t> permutation, const void* src, void* dst,
                           std::size_t element_size) {
  const Index count = permutation.size();
  if (element_size % 4 == 0) {
    using W = std::uint32_t;
    particle_for(policy, count,
                 permute_detail::GatherElements<W>{permutation, static_cast<const W*>(src), static_cast<W*>(dst),
                                                   element_size / 4});
  } else {
    using W = unsigned char;
    particle_for(policy, count,
                 permute_detail::GatherElements<W>{permutation, static_cast<const W*>(src), static_cast<W*>(dst),
                                                   element_size});
  }
}

// Copies `bytes` bytes between distinct arrays in the policy's memory space.
template <ExecutionPolicy P>
void copy_bytes(P policy, const void* src, void* dst, std::size_t bytes) {
  if (bytes % 4 == 0) {
    using W = std::uint32_t;
    particle_for(policy, bytes / 4, permute_detail::CopyWords<W>{static_cast<const W*>(src), static_cast<W*>(dst)});
  } else {
    using W = unsigned char;
    particle_for(policy, bytes, permute_detail::CopyWords<W>{static_cast<const W*>(src), static_cast<W*>(dst)});
  }
}

}  // namespace unisph
