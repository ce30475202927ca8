// Atomic add, min, max and compare-and-swap on one address, for both backends. Each returns the
// previous value.
//
// Device: the native atomics where CUDA has them (add on 32/64-bit integers, float and double;
// min/max on integers), a compare-and-swap loop otherwise (float/double min and max).
// Host: GCC's __atomic builtins, relaxed ordering (a parallel loop's end is the synchronisation
// point; no atomic here orders other memory).
#pragma once

#include <cstdint>
#include <type_traits>

#include "kernels/core/hd.h"

#if defined(__CUDACC__)
#include <cooperative_groups.h>
#include <cooperative_groups/reduce.h>
#endif

namespace romp {
namespace detail {

template <class T>
inline constexpr bool kAtomicType = std::is_same_v<T, float> || std::is_same_v<T, double> ||
                                    (std::is_integral_v<T> && (sizeof(T) == 4 || sizeof(T) == 8) &&
                                     !std::is_same_v<T, bool>);

struct AtomicAddOp {
  template <class T>
  ROMP_HD_INLINE static T apply(T a, T b) {
    return a + b;
  }
  template <class T>
  ROMP_HD_INLINE static bool changes(T, T) {
    return true;
  }
};
struct AtomicMinOp {
  template <class T>
  ROMP_HD_INLINE static T apply(T, T b) {
    return b;
  }
  template <class T>
  ROMP_HD_INLINE static bool changes(T old, T value) {
    return value < old;
  }
};
struct AtomicMaxOp {
  template <class T>
  ROMP_HD_INLINE static T apply(T, T b) {
    return b;
  }
  template <class T>
  ROMP_HD_INLINE static bool changes(T old, T value) {
    return old < value;
  }
};

#if defined(__CUDA_ARCH__)
// The CUDA integer type of the same width and signedness, for the native intrinsics.
template <class T>
using CudaInt = std::conditional_t<sizeof(T) == 4, std::conditional_t<std::is_signed_v<T>, int, unsigned int>,
                                   std::conditional_t<std::is_signed_v<T>, long long, unsigned long long>>;
// Bit patterns of floating-point values, for compare-and-swap on the word that holds them.
__device__ __forceinline__ unsigned int to_word(float x) { return __float_as_uint(x); }
__device__ __forceinline__ unsigned long long to_word(double x) { return __double_as_longlong(x); }
__device__ __forceinline__ float from_word(unsigned int w, float) { return __uint_as_float(w); }
__device__ __forceinline__ double from_word(unsigned long long w, double) { return __longlong_as_double(w); }

template <class Op, class T>
__device__ T device_cas_loop(T* address, T value) {
  using Word = decltype(to_word(value));
  Word* word_address = reinterpret_cast<Word*>(address);
  Word old_word = *word_address;
  while (true) {
    const T old = from_word(old_word, value);
    if (!Op::changes(old, value)) return old;
    const Word new_word = to_word(Op::apply(old, value));
    const Word seen = atomicCAS(word_address, old_word, new_word);
    if (seen == old_word) return old;
    old_word = seen;
  }
}
#else
template <class Op, class T>
inline T host_cas_loop(T* address, T value) {
  T old;
  __atomic_load(address, &old, __ATOMIC_RELAXED);
  while (Op::changes(old, value)) {
    T desired = Op::apply(old, value);
    if (__atomic_compare_exchange(address, &old, &desired, /*weak=*/true, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) break;
  }
  return old;
}
#endif

}  // namespace detail

template <class T>
ROMP_HD_INLINE T atomic_add(T* address, T value) {
  static_assert(detail::kAtomicType<T>, "atomic_add: 32/64-bit integers, float or double");
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_floating_point_v<T>) {
    return atomicAdd(address, value);
  } else if constexpr (sizeof(T) == 4) {
    using U = detail::CudaInt<T>;
    return T(atomicAdd(reinterpret_cast<U*>(address), U(value)));
  } else {
    // Two's-complement addition is the same for signed and unsigned 64-bit words.
    using U = unsigned long long;
    return T(atomicAdd(reinterpret_cast<U*>(address), U(value)));
  }
#else
  if constexpr (std::is_integral_v<T>) {
    return __atomic_fetch_add(address, value, __ATOMIC_RELAXED);
  } else {
    return detail::host_cas_loop<detail::AtomicAddOp>(address, value);
  }
#endif
}

template <class T>
ROMP_HD_INLINE T atomic_min(T* address, T value) {
  static_assert(detail::kAtomicType<T>, "atomic_min: 32/64-bit integers, float or double");
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_integral_v<T>) {
    using U = detail::CudaInt<T>;
    return T(atomicMin(reinterpret_cast<U*>(address), U(value)));
  } else {
    return detail::device_cas_loop<detail::AtomicMinOp>(address, value);
  }
#else
  return detail::host_cas_loop<detail::AtomicMinOp>(address, value);
#endif
}

template <class T>
ROMP_HD_INLINE T atomic_max(T* address, T value) {
  static_assert(detail::kAtomicType<T>, "atomic_max: 32/64-bit integers, float or double");
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_integral_v<T>) {
    using U = detail::CudaInt<T>;
    return T(atomicMax(reinterpret_cast<U*>(address), U(value)));
  } else {
    return detail::device_cas_loop<detail::AtomicMaxOp>(address, value);
  }
#else
  return detail::host_cas_loop<detail::AtomicMaxOp>(address, value);
#endif
}

// Writes `desired` if the address holds `expected`; returns what it held (== expected on success).
// 64-bit unsigned words only: what hash tables of packed keys need.
ROMP_HD_INLINE std::uint64_t atomic_cas(std::uint64_t* address, std::uint64_t expected, std::uint64_t desired) {
#if defined(__CUDA_ARCH__)
  using U = unsigned long long;
  return std::uint64_t(atomicCAS(reinterpret_cast<U*>(address), U(expected), U(desired)));
#else
  __atomic_compare_exchange_n(address, &expected, desired, /*weak=*/false, __ATOMIC_RELAXED, __ATOMIC_RELAXED);
  return expected;
#endif
}

// atomic_add for many threads adding into one address (a running total): on the device the threads of
// a warp that call it together add their values first (cooperative groups' reduce over the active
// lanes) and one of them adds the sum, a 32nd of the atomics that serialise at the address. The same
// total as atomic_add; floating-point sums in another order. Returns nothing: no lane sees a prefix.
template <class T>
ROMP_HD_INLINE void atomic_add_to_total(T* address, T value) {
#if defined(__CUDA_ARCH__)
  namespace cg = cooperative_groups;
  const cg::coalesced_group active = cg::coalesced_threads();
  const T sum = cg::reduce(active, value, cg::plus<T>());
  if (active.thread_rank() == 0) atomic_add(address, sum);
#else
  atomic_add(address, value);
#endif
}

}  // namespace romp
