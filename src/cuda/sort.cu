// Device radix sort of (key, value) pairs on CUB, compiled once into the library.

#include <cub/device/device_radix_sort.cuh>

#include "unisph/exec/backend/cuda/primitives.hpp"
#include "unisph/exec/backend/cuda/runtime.hpp"

namespace unisph::cuda {

namespace {
constexpr std::size_t round_up(std::size_t bytes) { return (bytes + 255) / 256 * 256; }
}  // namespace

template <class K, class V>
void sort_pairs(K* keys, V* values, Index n, int begin_bit, int end_bit) {
  if (n < 2 || begin_bit >= end_bit) return;
  cudaStream_t stream = static_cast<cudaStream_t>(stream_handle());
  // The double-buffer form needs no copy of the input and lets CUB ping-pong between the
  // caller's arrays and alternates in scratch storage.
  const std::size_t key_bytes = round_up(n * sizeof(K));
  const std::size_t value_bytes = round_up(n * sizeof(V));
  cub::DoubleBuffer<K> key_buffer(keys, nullptr);
  cub::DoubleBuffer<V> value_buffer(values, nullptr);
  std::size_t temp_bytes = 0;
  check(cub::DeviceRadixSort::SortPairs(nullptr, temp_bytes, key_buffer, value_buffer, n, begin_bit, end_bit, stream),
        "sizing sort_pairs");
  char* base = static_cast<char*>(scratch(key_bytes + value_bytes + temp_bytes, "sort_pairs"));
  key_buffer = cub::DoubleBuffer<K>(keys, reinterpret_cast<K*>(base));
  value_buffer = cub::DoubleBuffer<V>(values, reinterpret_cast<V*>(base + key_bytes));
  check(cub::DeviceRadixSort::SortPairs(base + key_bytes + value_bytes, temp_bytes, key_buffer, value_buffer, n,
                                        begin_bit, end_bit, stream),
        "sort_pairs of " + std::to_string(n) + " pairs");
  // An odd number of passes leaves the result in the alternates: bring it home.
  if (key_buffer.Current() != keys) copy_on_device(keys, key_buffer.Current(), n * sizeof(K), "sort_pairs keys");
  if (value_buffer.Current() != values)
    copy_on_device(values, value_buffer.Current(), n * sizeof(V), "sort_pairs values");
}

#define UNISPH_INSTANTIATE_SORT(K, V) template void sort_pairs<K, V>(K*, V*, Index, int, int);
UNISPH_CUDA_SORT_TYPES(UNISPH_INSTANTIATE_SORT)

}  // namespace unisph::cuda
