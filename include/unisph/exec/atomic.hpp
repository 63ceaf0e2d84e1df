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
