#pragma once
// Reordering an array of any element type by a permutation, on every policy:
//   dst[k] = src[permutation[k]]   for k < count
// It works on the bytes of the elements (in 4-byte words where the size allows), so one
// compiled kernel serves every variable type of a registry.

#include <cstdint>
#include <string_view>

#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/backend/cuda/runtime.hpp"
#include "unisph/memory/discrete_variable.hpp"

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

// Reorders the first permutation.size() elements of `data` (the policy's memory space) in
// place: element k becomes the old element permutation[k], through a temporary. On the device
// the temporary is the algorithms' scratch (cuda::scratch: stream order keeps the algorithm
// that made the permutation, a sort or a scan, from still using it), so that no particle set
// or plan holds a buffer of its own (12 bytes per particle in 3D float, as much as the
// positions); on the host it is `host_scratch`, grown as needed and kept.
template <ExecutionPolicy P>
void permute_in_place(P policy, View<const std::uint32_t> permutation, void* data, std::size_t element_size,
                      DiscreteVariable<std::uint32_t>& host_scratch, std::string_view what) {
  const std::size_t bytes = permutation.size() * element_size;
  if (bytes == 0) return;
  void* tmp = nullptr;
  if constexpr (P::space == MemorySpace::device) {
    tmp = cuda::scratch(bytes, what);
  } else {
    const Index words = Index((bytes + 3) / 4);
    if (host_scratch.size() < words) host_scratch.resize(words);
    tmp = host_scratch.write(policy).data();
  }
  gather_by_permutation(policy, permutation, data, tmp, element_size);
  copy_bytes(policy, tmp, data, bytes);
}

}  // namespace unisph
