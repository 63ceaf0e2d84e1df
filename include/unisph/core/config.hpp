#pragma once
// Compile-time configuration shared by every layer: the host/device function marker,
// the index type and the floating-point type chosen when unisph was configured.

#include <cstddef>
#include <cstdint>

#if defined(__CUDACC__)
#define UNISPH_HOST_DEVICE __host__ __device__
#define UNISPH_DEVICE __device__
#else
#define UNISPH_HOST_DEVICE
#define UNISPH_DEVICE
#endif

// Inlined wherever it is called, whatever the optimiser's cost model says. For the few small
// functions whose only effect the optimiser cannot see (a prefetch: GCC 12 took a function that
// only prefetches as free of effects and dropped the calls to it).
#if defined(__CUDACC__)
#define UNISPH_ALWAYS_INLINE __forceinline__
#elif defined(__GNUC__)
#define UNISPH_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define UNISPH_ALWAYS_INLINE inline
#endif

// True while nvcc compiles the device side of a translation unit.
#if defined(__CUDA_ARCH__)
#define UNISPH_DEVICE_CODE 1
#else
#define UNISPH_DEVICE_CODE 0
#endif

// UNISPH_HAS_CUDA is set by the build (1 when the CUDA backend is compiled into the library).
#ifndef UNISPH_HAS_CUDA
#define UNISPH_HAS_CUDA 0
#endif

namespace unisph {

// Item counts and indices. 64-bit so that a GPU with 80 GiB can hold more than 2^32 bytes
// of one array without overflow in byte offsets.
using Index = std::size_t;

#if defined(UNISPH_SINGLE_PRECISION) && UNISPH_SINGLE_PRECISION
using Real = float;
#else
using Real = double;
#endif

}  // namespace unisph
