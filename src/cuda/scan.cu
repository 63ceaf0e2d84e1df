// Device exclusive scan on CUB, compiled once into the library.

#include <cub/device/device_scan.cuh>

#include "unisph/exec/backend/cuda/primitives.hpp"
#include "unisph/exec/backend/cuda/runtime.hpp"

namespace unisph::cuda {

namespace {
template <class T>
__global__ void write_total(const T* last_input, T* out, Index n) {
  out[n] = out[n - 1] + *last_input;
}
}  // namespace

template <class T>
void exclusive_scan(const T* in, T* out, Index n, bool with_total) {
  cudaStream_t stream = static_cast<cudaStream_t>(stream_handle());
  if (n == 0) {
    if (with_total) fill_zero(out, sizeof(T), "exclusive_scan of 0 items");
    return;
  }
  std::size_t temp_bytes = 0;
  check(cub::DeviceScan::ExclusiveSum(nullptr, temp_bytes, in, out, n, stream), "sizing exclusive_scan");
  // Scratch: [last input (for the total when scanning in place) | CUB temporaries].
  constexpr std::size_t head = 256;
  char* scratch_base = static_cast<char*>(scratch(head + temp_bytes, "exclusive_scan"));
  T* last = reinterpret_cast<T*>(scratch_base);
  if (with_total) copy_on_device(last, in + (n - 1), sizeof(T), "exclusive_scan total");
  check(cub::DeviceScan::ExclusiveSum(scratch_base + head, temp_bytes, in, out, n, stream),
        "exclusive_scan of " + std::to_string(n) + " items");
  if (with_total) {
    write_total<<<1, 1, 0, stream>>>(last, out, n);
    check_launch("exclusive_scan total", 1);
  }
}

#define UNISPH_INSTANTIATE_SCAN(T) template void exclusive_scan<T>(const T*, T*, Index, bool);
UNISPH_CUDA_SCAN_TYPES(UNISPH_INSTANTIATE_SCAN)

}  // namespace unisph::cuda
