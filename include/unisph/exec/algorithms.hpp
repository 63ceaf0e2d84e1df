#pragma once
// The front end of the execution layer: one signature for every policy.
//
//   particle_for(policy, n, kernel)                    kernel(i) for i in [0, n)
//   particle_reduce(policy, n, op, f)                  op-combination of f(i); op = Sum<T>, Min<T>, Max<T>...
//   particle_reduce(policy, n, identity, op, f)        any associative op with its identity
//   deterministic_reduce(policy, n, op, f)             the same with one association on every policy:
//   deterministic_reduce(policy, n, identity, op, f)   the same bits on seq, par and the GPU
//   exclusive_scan(policy, in, out)                    out[i] = in[0] + ... + in[i-1]; out may be in;
//                                                      out.size() == n + 1 also writes the total to out[n]
//   sort_pairs(policy, keys, values [, begin_bit, end_bit])   stable radix sort by unsigned 32/64-bit keys
//   fence(policy)                                      waits until the policy's work so far is done
//
// Views passed to an algorithm must live in the policy's memory space; the overloads taking
// variables do the coherence themselves. Device work is asynchronous on unisph's stream: only
// particle_reduce (its result is a host value) and host accesses to variables wait.
//
// Kernels are trivially copyable function objects with a UNISPH_HOST_DEVICE call operator;
// they are copied by value into the launch.

#include <cstdint>
#include <string>
#include <type_traits>

#include "unisph/core/error.hpp"
#include "unisph/exec/backend/seq/algorithms.hpp"
#include "unisph/exec/backend/tbb/algorithms.hpp"
#include "unisph/exec/policy.hpp"
#include "unisph/exec/reduce_ops.hpp"
#include "unisph/memory/discrete_variable.hpp"
#include "unisph/memory/view.hpp"

#if UNISPH_HAS_CUDA && defined(__CUDACC__)
#include "unisph/exec/backend/cuda/algorithms.cuh"
#else
#include "unisph/exec/backend/cuda/absent.hpp"
#endif

namespace unisph {

namespace detail {
template <class F>
constexpr void check_kernel() {
  static_assert(std::is_trivially_copyable_v<F>,
                "a unisph kernel is copied byte for byte into every launch (to the GPU as well), so it must be "
                "trivially copyable: hold Views and plain values, not std::vector, references or virtual functions.");
}

// Scan and sort run on the same-width fixed-size type, so that int / long / long long reach
// one compiled implementation.
template <class T>
using canonical_scan_t = std::conditional_t<
    std::is_floating_point_v<T>, T,
    std::conditional_t<sizeof(T) == 4, std::conditional_t<std::is_signed_v<T>, std::int32_t, std::uint32_t>,
                       std::conditional_t<std::is_signed_v<T>, std::int64_t, std::uint64_t>>>;
template <class V>
using sort_value_bits_t = std::conditional_t<sizeof(V) == 4, std::uint32_t, std::uint64_t>;
}  // namespace detail

// Waits for every launch and copy issued so far on the policy (host policies finish before returning).
template <ExecutionPolicy P>
void fence(P) {
  if constexpr (P::space == MemorySpace::device) cuda::synchronize("fence(par_device)");
}

template <ExecutionPolicy P, class F>
void particle_for(P, Index n, const F& kernel) {
  detail::check_kernel<F>();
  backend::Backend<P>::particle_for(n, kernel);
}

template <ExecutionPolicy P, class T, class Op, class F>
T particle_reduce(P, Index n, T identity, const Op& op, const F& f) {
  detail::check_kernel<F>();
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_copyable_v<Op>,
                "particle_reduce moves partial results and the operation between threads and devices byte for byte, "
                "so the value type and the operation must be trivially copyable.");
  return backend::Backend<P>::particle_reduce(n, identity, op, f);
}

template <ExecutionPolicy P, class Op, class F>
auto particle_reduce(P policy, Index n, const Op& op, const F& f) {
  static_assert(requires { Op::identity(); },
                "this particle_reduce needs an operation that knows its identity (Sum<T>, Min<T>, Max<T>); for other "
                "operations call particle_reduce(policy, n, identity, op, f).");
  return particle_reduce(policy, n, Op::identity(), op, f);
}

// particle_reduce's association depends on the policy (par: oneTBB's deterministic split; GPU:
// one wave of blocks), so a floating-point sum differs in the last bits between policies, which
// is enough to part trajectories that take decisions on it (FIRE's power in the relaxation).
// deterministic_reduce combines in the one association of backend/reduction_tree.hpp on every
// backend: a floating-point result has the same bits on every policy and for any thread count,
// provided f(i) has (docs/architecture.md). It costs a pass over a small array more than
// particle_reduce on the host and one launch per level on the GPU.
template <ExecutionPolicy P, class T, class Op, class F>
T deterministic_reduce(P, Index n, T identity, const Op& op, const F& f) {
  detail::check_kernel<F>();
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_copyable_v<Op>,
                "deterministic_reduce moves partial results and the operation between threads and devices byte for "
                "byte, so the value type and the operation must be trivially copyable.");
  return backend::Backend<P>::deterministic_reduce(n, identity, op, f);
}

template <ExecutionPolicy P, class Op, class F>
auto deterministic_reduce(P policy, Index n, const Op& op, const F& f) {
  static_assert(requires { Op::identity(); },
                "this deterministic_reduce needs an operation that knows its identity (Sum<T>, Min<T>, Max<T>); for "
                "other operations call deterministic_reduce(policy, n, identity, op, f).");
  return deterministic_reduce(policy, n, Op::identity(), op, f);
}

template <ExecutionPolicy P, class T>
void exclusive_scan(P, View<const T> in, View<T> out) {
  static_assert(std::is_arithmetic_v<T> && sizeof(T) >= 4,
                "exclusive_scan works on 32- and 64-bit integers, float and double.");
  const Index n = in.size();
  if (out.size() != n && out.size() != n + 1)
    throw Error("exclusive_scan: the output has " + std::to_string(out.size()) + " elements for " +
                std::to_string(n) + " inputs; it needs n (or n + 1 to receive the total)");
  using C = detail::canonical_scan_t<T>;
  backend::Backend<P>::exclusive_scan(reinterpret_cast<const C*>(in.data()), reinterpret_cast<C*>(out.data()), n,
                                      out.size() == n + 1);
}
template <ExecutionPolicy P, class T>
void exclusive_scan(P policy, View<T> in, View<T> out) {
  exclusive_scan(policy, View<const T>(in), out);
}

template <ExecutionPolicy P, class K, class V>
void sort_pairs(P, View<K> keys, View<V> values, int begin_bit = 0, int end_bit = int(8 * sizeof(K))) {
  static_assert(std::is_same_v<K, std::uint32_t> || std::is_same_v<K, std::uint64_t>,
                "sort_pairs sorts 32- and 64-bit unsigned keys (std::uint32_t or std::uint64_t).");
  static_assert(std::is_trivially_copyable_v<V> && (sizeof(V) == 4 || sizeof(V) == 8),
                "sort_pairs carries 4- or 8-byte values (an index, a float, a double); to reorder anything larger, "
                "sort (key, index) pairs and gather with the sorted indices.");
  if (keys.size() != values.size())
    throw Error("sort_pairs: " + std::to_string(keys.size()) + " keys but " + std::to_string(values.size()) +
                " values");
  if (begin_bit < 0 || end_bit > int(8 * sizeof(K)) || begin_bit > end_bit)
    throw Error("sort_pairs: the bit range [" + std::to_string(begin_bit) + ", " + std::to_string(end_bit) +
                ") does not fit a " + std::to_string(8 * sizeof(K)) + "-bit key");
  using Bits = detail::sort_value_bits_t<V>;
  backend::Backend<P>::sort_pairs(keys.data(), reinterpret_cast<Bits*>(values.data()), keys.size(), begin_bit,
                                  end_bit);
}

// The same on variables, which are made coherent in the policy's memory space first.
template <ExecutionPolicy P, class T>
void exclusive_scan(P policy, DiscreteVariable<T>& in, DiscreteVariable<T>& out) {
  if (&in == &out) {
    exclusive_scan(policy, View<const T>(in.read_write(policy)), in.read_write(policy));
    return;
  }
  View<const T> input = in.read(policy);
  exclusive_scan(policy, input, out.write(policy));
}

template <ExecutionPolicy P, class K, class V>
void sort_pairs(P policy, DiscreteVariable<K>& keys, DiscreteVariable<V>& values, int begin_bit = 0,
                int end_bit = int(8 * sizeof(K))) {
  sort_pairs(policy, keys.read_write(policy), values.read_write(policy), begin_bit, end_bit);
}

}  // namespace unisph
