#pragma once
// The CUDA backend: kernels launched asynchronously on unisph's stream. Only the reduction
// waits, because its result is a host value. Included by the front end only when nvcc compiles.

#include <cuda_runtime.h>

#include <cub/block/block_reduce.cuh>

#include "unisph/exec/backend/backend.hpp"
#include "unisph/exec/backend/cuda/primitives.hpp"
#include "unisph/exec/backend/cuda/runtime.hpp"
#include "unisph/exec/backend/reduction_tree.hpp"
#include "unisph/exec/occupancy_hint.hpp"

namespace unisph::backend {

namespace cuda_detail {

inline constexpr int block_size = 256;

inline cudaStream_t stream() { return static_cast<cudaStream_t>(cuda::stream_handle()); }

// One item per thread; the loop only turns when n exceeds the largest grid (2^31 - 1 blocks).
template <class F>
__global__ void __launch_bounds__(block_size) particle_for_kernel(Index n, F f) {
  const Index stride = static_cast<Index>(gridDim.x) * block_size;
  for (Index i = static_cast<Index>(blockIdx.x) * block_size + threadIdx.x; i < n; i += stride) f(i);
}
// The same for a kernel with an occupancy hint (exec/occupancy_hint.hpp). A separate kernel, since
// __launch_bounds__(n, 1) is not the same as __launch_bounds__(n) to nvcc: measured, it gave other
// kernels more registers than without the second argument.
template <class F>
__global__ void __launch_bounds__(block_size, min_blocks_per_multiprocessor<F>()) particle_for_kernel_hinted(Index n, F f) {
  const Index stride = static_cast<Index>(gridDim.x) * block_size;
  for (Index i = static_cast<Index>(blockIdx.x) * block_size + threadIdx.x; i < n; i += stride) f(i);
}

inline constexpr Index max_blocks = 2147483647;

// First pass: each block reduces a grid-stride slice. Four independent items per trip keep
// several loads in flight per thread (the reduction is bound by memory bandwidth).
template <class T, class Op, class F>
__global__ void __launch_bounds__(block_size) reduce_blocks(Index n, T identity, Op op, F f, T* partials) {
  const Index stride = static_cast<Index>(gridDim.x) * block_size;
  Index i = static_cast<Index>(blockIdx.x) * block_size + threadIdx.x;
  T acc = identity;
  for (; i + 3 * stride < n; i += 4 * stride) {
    const T a = f(i), b = f(i + stride), c = f(i + 2 * stride), d = f(i + 3 * stride);
    acc = op(acc, op(op(a, b), op(c, d)));
  }
  for (; i < n; i += stride) acc = op(acc, f(i));
  using BlockReduce = cub::BlockReduce<T, block_size>;
  __shared__ typename BlockReduce::TempStorage storage;
  const T block_total = BlockReduce(storage).Reduce(acc, op);
  if (threadIdx.x == 0) partials[blockIdx.x] = block_total;
}

// Second pass: one block combines the partials in a fixed order (deterministic results).
template <class T, class Op>
__global__ void __launch_bounds__(block_size) reduce_partials(int count, T identity, Op op, const T* partials, T* result) {
  T acc = identity;
  for (int i = threadIdx.x; i < count; i += block_size) acc = op(acc, partials[i]);
  using BlockReduce = cub::BlockReduce<T, block_size>;
  __shared__ typename BlockReduce::TempStorage storage;
  const T total = BlockReduce(storage).Reduce(acc, op);
  if (threadIdx.x == 0) *result = total;
}

// One level of deterministic_reduce: block b reduces items [b W, b W + W) (the identity past
// count) by the halving tree of reduction_tree.hpp in shared memory, the same association as
// the host's; coalesced loads, one item per thread.
static_assert(reduction_tree_width == block_size, "a tree block is one CUDA block");
template <class T, class Op, class F>
__global__ void __launch_bounds__(block_size) tree_reduce_level(Index count, Index blocks, T identity, Op op, F f,
                                                                T* out) {
  __shared__ alignas(T) unsigned char storage[block_size * sizeof(T)];
  T* v = reinterpret_cast<T*>(storage);
  const Index t = threadIdx.x;
  for (Index b = blockIdx.x; b < blocks; b += gridDim.x) {
    const Index i = b * block_size + t;
    v[t] = i < count ? f(i) : identity;
    __syncthreads();
    for (Index s = block_size / 2; s > 0; s /= 2) {
      if (t < s) v[t] = op(v[t], v[t + s]);
      __syncthreads();
    }
    if (t == 0) out[b] = v[0];
    __syncthreads();  // v is refilled for the next block
  }
}

// The items of a level above the first: the previous level's block results.
template <class T>
struct TreeLevelValues {
  const T* values;
  __device__ T operator()(Index i) const { return values[i]; }
};

}  // namespace cuda_detail

template <>
struct Backend<ParallelDevicePolicy> {
  template <class F>
  static void particle_for(Index n, const F& f) {
    cuda::require_device();
    if (n == 0) return;
    Index blocks = (n + cuda_detail::block_size - 1) / cuda_detail::block_size;
    if (blocks > cuda_detail::max_blocks) blocks = cuda_detail::max_blocks;
    if constexpr (min_blocks_per_multiprocessor<F>() > 0)
      cuda_detail::particle_for_kernel_hinted<<<static_cast<unsigned>(blocks), cuda_detail::block_size, 0, cuda_detail::stream()>>>(n, f);
    else
      cuda_detail::particle_for_kernel<<<static_cast<unsigned>(blocks), cuda_detail::block_size, 0, cuda_detail::stream()>>>(n, f);
    cuda::check_launch("particle_for", n);
  }

  template <class T, class Op, class F>
  static T particle_reduce(Index n, T identity, const Op& op, const F& f) {
    cuda::require_device();
    if (n == 0) return identity;
    // One full wave of resident blocks (8 blocks of 256 threads fill an SM's 2048 threads).
    const Index wave = static_cast<Index>(cuda::multiprocessor_count()) * 8;
    const Index needed = (n + cuda_detail::block_size - 1) / cuda_detail::block_size;
    const int blocks = static_cast<int>(needed < wave ? needed : wave);
    static_assert(sizeof(T) <= cuda::pinned_result_bytes,
                  "particle_reduce on the device returns values of at most 256 bytes.");
    T* partials = static_cast<T*>(cuda::scratch(sizeof(T) * blocks, "particle_reduce"));
    // Mapped pinned memory: the final pass writes the result straight into host memory.
    T* result = static_cast<T*>(cuda::pinned_result_buffer());
    cuda_detail::reduce_blocks<<<blocks, cuda_detail::block_size, 0, cuda_detail::stream()>>>(n, identity, op, f, partials);
    cuda::check_launch("particle_reduce", n);
    cuda_detail::reduce_partials<<<1, cuda_detail::block_size, 0, cuda_detail::stream()>>>(blocks, identity, op, partials, result);
    cuda::check_launch("particle_reduce (final pass)", static_cast<Index>(blocks));
    cuda::synchronize("particle_reduce");
    return *result;
  }

  // The association of reduction_tree.hpp, one launch per level (10^6 items: 3 launches), the
  // last writing into the mapped result buffer; the host's bits (seq, par) exactly.
  template <class T, class Op, class F>
  static T deterministic_reduce(Index n, T identity, const Op& op, const F& f) {
    cuda::require_device();
    if (n == 0) return identity;
    static_assert(sizeof(T) <= cuda::pinned_result_bytes,
                  "deterministic_reduce on the device returns values of at most 256 bytes.");
    Index scratch_items = 0;
    for (Index count = reduction_tree_blocks(n); count > 1; count = reduction_tree_blocks(count)) scratch_items += count;
    T* partials = static_cast<T*>(cuda::scratch(sizeof(T) * (scratch_items > 0 ? scratch_items : 1), "deterministic_reduce"));
    T* result = static_cast<T*>(cuda::pinned_result_buffer());
    const auto grid = [](Index blocks) {
      return static_cast<unsigned>(blocks < cuda_detail::max_blocks ? blocks : cuda_detail::max_blocks);
    };
    Index blocks = reduction_tree_blocks(n);
    T* out = blocks > 1 ? partials : result;
    cuda_detail::tree_reduce_level<<<grid(blocks), cuda_detail::block_size, 0, cuda_detail::stream()>>>(n, blocks, identity, op, f, out);
    cuda::check_launch("deterministic_reduce", n);
    while (blocks > 1) {
      const Index count = blocks;
      const T* in = out;
      blocks = reduction_tree_blocks(count);
      out = blocks > 1 ? out + count : result;
      cuda_detail::tree_reduce_level<<<grid(blocks), cuda_detail::block_size, 0, cuda_detail::stream()>>>(
          count, blocks, identity, op, cuda_detail::TreeLevelValues<T>{in}, out);
      cuda::check_launch("deterministic_reduce (upper level)", count);
    }
    cuda::synchronize("deterministic_reduce");
    return *result;
  }

  template <class T>
  static void exclusive_scan(const T* in, T* out, Index n, bool with_total) {
    cuda::require_device();
    cuda::exclusive_scan(in, out, n, with_total);
  }

  template <class K, class V>
  static void sort_pairs(K* keys, V* values, Index n, int begin_bit, int end_bit) {
    cuda::require_device();
    cuda::sort_pairs(keys, values, n, begin_bit, end_bit);
  }
};

}  // namespace unisph::backend
