#pragma once
// Products and sums that are never fused into a multiply-add, so that host and device round
// every pair distance the same way and every policy decides every neighbour pair alike.
//
// Why this is needed: nvcc fuses a * b + c into one FMA by default (-fmad=true), and a host
// compiler may do the same when the target has FMA instructions and contraction is allowed
// (GCC's default in GNU mode, e.g. -std=gnu++20 -march=native). A fused r^2 differs from the
// separately rounded one in the last bit, which flips pairs lying at the cutoff.
//
// How it is guaranteed here, for this code only (the rest of a translation unit keeps FMA):
//   device: the round-to-nearest intrinsics __fmul_rn / __dmul_rn and __fadd_rn / __dadd_rn,
//           which nvcc documents as never merged into a multiply-add;
//   host:   on targets with FMA instructions (x86 with -mfma or -march=haswell and later,
//           every AArch64), the product passes through an empty asm statement, which the
//           optimiser cannot see through and therefore cannot fuse into the following add.
//           Without FMA instructions the host cannot contract at all.
// Only the product needs the barrier: contraction fuses a multiply into a later add.

#include <type_traits>

#include "unisph/core/config.hpp"

namespace unisph::uncontracted {

template <class T>
UNISPH_HOST_DEVICE inline T mul(T a, T b) {
  static_assert(std::is_floating_point_v<T>, "unisph::uncontracted works on float and double.");
#if UNISPH_DEVICE_CODE
  if constexpr (std::is_same_v<T, float>)
    return __fmul_rn(a, b);
  else
    return __dmul_rn(a, b);
#else
  T product = a * b;
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__)) && defined(__FMA__)
  asm("" : "+x"(product));
#elif defined(__GNUC__) && defined(__aarch64__)
  asm("" : "+w"(product));
#endif
  return product;
#endif
}

template <class T>
UNISPH_HOST_DEVICE inline T add(T a, T b) {
#if UNISPH_DEVICE_CODE
  if constexpr (std::is_same_v<T, float>)
    return __fadd_rn(a, b);
  else
    return __dadd_rn(a, b);
#else
  return a + b;
#endif
}

template <class T>
UNISPH_HOST_DEVICE inline T sub(T a, T b) {
#if UNISPH_DEVICE_CODE
  if constexpr (std::is_same_v<T, float>)
    return __fsub_rn(a, b);
  else
    return __dsub_rn(a, b);
#else
  return a - b;
#endif
}

}  // namespace unisph::uncontracted
