#pragma once
// Atomics usable inside kernels on every policy. On the host they are std::atomic_ref
// operations (relaxed: they order nothing but the counter itself); on the device they are
// CUDA's atomics.
//
//   atomic_fetch_add(&x, v) -> old value     atomic_add(&x, v)
//   atomic_min(&x, v)      atomic_max(&x, v)  (return the old value too)
// Supported: int, unsigned, long long, unsigned long long (and the fixed-width types that are
// the same), float and double.

#include <atomic>
#include <cstdint>
#include <type_traits>

#include "unisph/core/config.hpp"

namespace unisph {

namespace detail {
template <class T>
inline constexpr bool atomic_supported_v =
    std::is_same_v<T, int> || std::is_same_v<T, unsigned> || std::is_same_v<T, long long> ||
    std::is_same_v<T, unsigned long long> || std::is_same_v<T, long> || std::is_same_v<T, unsigned long> ||
    std::is_same_v<T, float> || std::is_same_v<T, double>;

#if defined(__CUDA_ARCH__)
// CUDA names 64-bit atomics with (unsigned) long long; long is the same width on Linux.
template <class T>
UNISPH_DEVICE auto* as_cuda(T* p) {
  if constexpr (std::is_same_v<T, long>)
    return reinterpret_cast<long long*>(p);
  else if constexpr (std::is_same_v<T, unsigned long>)
    return reinterpret_cast<unsigned long long*>(p);
  else
    return p;
}

// atomicAdd has no signed 64-bit overload; two's complement makes the unsigned one identical.
template <class T>
UNISPH_DEVICE T device_fetch_add(T* address, T value) {
  if constexpr (std::is_integral_v<T> && sizeof(T) == 8) {
    return static_cast<T>(atomicAdd(reinterpret_cast<unsigned long long*>(address), static_cast<unsigned long long>(value)));
  } else {
    return atomicAdd(address, value);
  }
}

template <class T, class Better>
UNISPH_DEVICE T cas_loop(T* address, Better better, T value) {
  // Floating-point min/max have no hardware atomic: compare-and-swap on the bit pattern.
  using Bits = std::conditional_t<sizeof(T) == 4, unsigned int, unsigned long long>;
  Bits* bits = reinterpret_cast<Bits*>(address);
  Bits old = *bits, assumed;
  do {
    assumed = old;
    T current;
    memcpy(&current, &assumed, sizeof(T));
    if (!better(value, current)) return current;
    Bits desired;
    memcpy(&desired, &value, sizeof(T));
    old = atomicCAS(bits, assumed, desired);
  } while (assumed != old);
  T previous;
  memcpy(&previous, &old, sizeof(T));
  return previous;
}
#endif

template <class T, class Better>
T host_cas_loop(T* address, Better better, T value) {
  std::atomic_ref<T> ref(*address);
  T current = ref.load(std::memory_order_relaxed);
  while (better(value, current) && !ref.compare_exchange_weak(current, value, std::memory_order_relaxed)) {
  }
  return current;
}

struct Less {
  template <class T>
  UNISPH_HOST_DEVICE bool operator()(const T& a, const T& b) const { return a < b; }
};
struct Greater {
  template <class T>
  UNISPH_HOST_DEVICE bool operator()(const T& a, const T& b) const { return b < a; }
};
}  // namespace detail

template <class T>
UNISPH_HOST_DEVICE T atomic_fetch_add(T* address, T value) {
  static_assert(detail::atomic_supported_v<T>,
                "unisph atomics support int, unsigned, long long, unsigned long long, float and double.");
#if defined(__CUDA_ARCH__)
  return detail::device_fetch_add(address, value);
#else
  return std::atomic_ref<T>(*address).fetch_add(value, std::memory_order_relaxed);
#endif
}

template <class T>
UNISPH_HOST_DEVICE void atomic_add(T* address, T value) {
  (void)atomic_fetch_add(address, value);
}

// atomic_fetch_add(counter, 1u) for counters that neighbouring threads often share (a cell's
// particle count when the particles are sorted): the old value, distinct and contiguous for
// every thread that increments the same counter. On the device a run of consecutive lanes of a
// warp that increment the same counter shares one atomic: the run's first lane adds the run's
// length, each lane takes its place in the run. A counter that appears in two runs of a warp
// gets two atomics, still correct. Runs rather than __match_any_sync: in random order every
// lane is a run of its own, and the match costs more than the few instructions here (measured
// on an H100, docs/neighbor_search.md).
UNISPH_HOST_DEVICE inline unsigned atomic_increment_shared(unsigned* counter) {
#if defined(__CUDA_ARCH__)
  const unsigned active = __activemask();
  if (active != 0xffffffffu) return atomicAdd(counter, 1u);  // a partial warp: no neighbours to trust
  unsigned lane;
  asm("mov.u32 %0, %%laneid;" : "=r"(lane));
  const unsigned long long address = reinterpret_cast<unsigned long long>(counter);
  const unsigned long long previous = __shfl_up_sync(active, address, 1);
  const unsigned heads = __ballot_sync(active, lane == 0 || previous != address);
  const unsigned head = 31u - static_cast<unsigned>(__clz(heads & (0xffffffffu >> (31u - lane))));
  const unsigned after = heads & ~(0xffffffffu >> (31u - lane));  // heads above this lane
  const unsigned end = after ? static_cast<unsigned>(__ffs(after)) - 1u : 32u;
  unsigned base = 0;
  if (lane == head) base = atomicAdd(counter, end - head);
  base = __shfl_sync(active, base, head);
  return base + (lane - head);
#else
  return std::atomic_ref<unsigned>(*counter).fetch_add(1u, std::memory_order_relaxed);
#endif
}

template <class T>
UNISPH_HOST_DEVICE T atomic_min(T* address, T value) {
  static_assert(detail::atomic_supported_v<T>,
                "unisph atomics support int, unsigned, long long, unsigned long long, float and double.");
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_floating_point_v<T>)
    return detail::cas_loop(address, detail::Less{}, value);
  else
    return static_cast<T>(atomicMin(detail::as_cuda(address), static_cast<std::remove_pointer_t<decltype(detail::as_cuda(address))>>(value)));
#else
  return detail::host_cas_loop(address, detail::Less{}, value);
#endif
}

template <class T>
UNISPH_HOST_DEVICE T atomic_max(T* address, T value) {
  static_assert(detail::atomic_supported_v<T>,
                "unisph atomics support int, unsigned, long long, unsigned long long, float and double.");
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_floating_point_v<T>)
    return detail::cas_loop(address, detail::Greater{}, value);
  else
    return static_cast<T>(atomicMax(detail::as_cuda(address), static_cast<std::remove_pointer_t<decltype(detail::as_cuda(address))>>(value)));
#else
  return detail::host_cas_loop(address, detail::Greater{}, value);
#endif
}

}  // namespace unisph
