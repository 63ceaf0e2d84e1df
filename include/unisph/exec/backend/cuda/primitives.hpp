#pragma once
// Device scan and radix sort, compiled once into the unisph library (src/cuda/*.cu) on top of
// CUB, so that user code does not instantiate CUB's sort in every translation unit.
// Supported element types: scan on int32, uint32, int64, uint64, float, double;
// sort on uint32 / uint64 keys with uint32 / uint64 values (other 4- and 8-byte values are
// sorted as their bit patterns by the front end).

#include <cstdint>

#include "unisph/core/config.hpp"

namespace unisph::cuda {

// out may alias in; with_total writes the sum of all n inputs to out[n].
template <class T>
void exclusive_scan(const T* in, T* out, Index n, bool with_total);

// Sorts keys in place by the bits [begin_bit, end_bit), stably, permuting values with them.
template <class K, class V>
void sort_pairs(K* keys, V* values, Index n, int begin_bit, int end_bit);

#define UNISPH_CUDA_SCAN_TYPES(X) X(std::int32_t) X(std::uint32_t) X(std::int64_t) X(std::uint64_t) X(float) X(double)
#define UNISPH_CUDA_SORT_TYPES(X) \
  X(std::uint32_t, std::uint32_t) X(std::uint32_t, std::uint64_t) X(std::uint64_t, std::uint32_t) X(std::uint64_t, std::uint64_t)

#define UNISPH_DECLARE_SCAN(T) extern template void exclusive_scan<T>(const T*, T*, Index, bool);
#define UNISPH_DECLARE_SORT(K, V) extern template void sort_pairs<K, V>(K*, V*, Index, int, int);
UNISPH_CUDA_SCAN_TYPES(UNISPH_DECLARE_SCAN)
UNISPH_CUDA_SORT_TYPES(UNISPH_DECLARE_SORT)
#undef UNISPH_DECLARE_SCAN
#undef UNISPH_DECLARE_SORT

}  // namespace unisph::cuda
