#pragma once
// Backend<ParallelDevicePolicy> where device kernels cannot be compiled: either this unisph has
// no CUDA backend (a run-time PolicyUnavailable error naming the reason, so that generic code
// still compiles), or it has one but this translation unit is not compiled by nvcc (a
// compile-time error: the kernel would have no device code).

#include "unisph/exec/backend/backend.hpp"
#include "unisph/exec/backend/cuda/primitives.hpp"
#include "unisph/exec/backend/cuda/runtime.hpp"

namespace unisph::backend {

template <>
struct Backend<ParallelDevicePolicy> {
  template <class F>
  static void particle_for(Index, const F&) {
#if UNISPH_HAS_CUDA
    static_assert(dependent_false_v<F>,
                  "particle_for(par_device, ...) launches a GPU kernel, so this source file must be compiled by nvcc: "
                  "list it in unisph_kernel_sources() in CMake (or give it LANGUAGE CUDA).");
#else
    require_policy(PolicyKind::device);
#endif
  }

  template <class T, class Op, class F>
  static T particle_reduce(Index, T identity, const Op&, const F&) {
#if UNISPH_HAS_CUDA
    static_assert(dependent_false_v<F>,
                  "particle_reduce(par_device, ...) launches a GPU kernel, so this source file must be compiled by "
                  "nvcc: list it in unisph_kernel_sources() in CMake (or give it LANGUAGE CUDA).");
#else
    require_policy(PolicyKind::device);
#endif
    return identity;
  }

  template <class T, class Op, class F>
  static T deterministic_reduce(Index, T identity, const Op&, const F&) {
#if UNISPH_HAS_CUDA
    static_assert(dependent_false_v<F>,
                  "deterministic_reduce(par_device, ...) launches a GPU kernel, so this source file must be compiled "
                  "by nvcc: list it in unisph_kernel_sources() in CMake (or give it LANGUAGE CUDA).");
#else
    require_policy(PolicyKind::device);
#endif
    return identity;
  }

  // Scan and sort are compiled into the library, so they work from any translation unit.
  template <class T>
  static void exclusive_scan(const T* in, T* out, Index n, bool with_total) {
    cuda::require_device();
#if UNISPH_HAS_CUDA
    cuda::exclusive_scan(in, out, n, with_total);
#else
    (void)in, (void)out, (void)n, (void)with_total;
#endif
  }

  template <class K, class V>
  static void sort_pairs(K* keys, V* values, Index n, int begin_bit, int end_bit) {
    cuda::require_device();
#if UNISPH_HAS_CUDA
    cuda::sort_pairs(keys, values, n, begin_bit, end_bit);
#else
    (void)keys, (void)values, (void)n, (void)begin_bit, (void)end_bit;
#endif
  }
};

}  // namespace unisph::backend
