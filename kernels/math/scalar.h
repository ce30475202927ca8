// Scalar helpers for single-source math: per-target square roots, selects and power-of-two scaling.
//
// The math in kernels/math and kernels/svd is written once for both targets, and on the CPU the batch
// launchers run it under `#pragma omp simd` so one SIMD lane handles one element. Two details of
// GCC's default floating-point model (-fmath-errno, -ftrapping-math, which the project keeps) would
// stop that vectorisation, and the helpers here are written to avoid them:
//   * std::sqrt may set errno, so GCC emits a scalar libm fallback beside every sqrt instruction.
//     The host rsqrt is therefore computed with Newton-Raphson steps from the classic bit-level
//     initial guess (Lomont 2003, "Fast inverse square root"), which is plain arithmetic.
//   * A conditional `c ? x * y : z` with a floating-point operation in an arm is not if-converted
//     (the operation might trap), so it stays a branch. select() blends bit patterns instead.
// On the device the same helpers are the hardware instructions: rsqrtf (MUFU.RSQ, the "fast
// reciprocal square root" of McAdams et al. 2011), sqrtf, and SEL for select().
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "kernels/core/hd.h"

// Forced inlining on both targets. ROMP_HD_INLINE is __forceinline__ under nvcc but only an `inline`
// hint in a C++-only build, where GCC then keeps the larger helpers (and the SVD itself) as calls,
// and a call in the body of an `omp simd` loop prevents its vectorisation.
#if defined(__CUDACC__)
#define ROMP_MATH_INLINE __host__ __device__ __forceinline__
#else
#define ROMP_MATH_INLINE inline __attribute__((always_inline))
#endif

namespace romp::math {
namespace detail {

// IEEE-754 binary32/binary64 layout: the unsigned word that holds a value and its exponent field.
template <class T>
struct FloatBits;
template <>
struct FloatBits<float> {
  using Word = std::uint32_t;
  static constexpr int kMantissaBits = 23;
  static constexpr Word kExponentMask = 0xffu;  // after shifting out the mantissa
  // Initial guess of 1/√x from the bits of x (Lomont 2003): relative error below 3.5e-2.
  static constexpr Word kRsqrtMagic = 0x5f375a86u;
  // Newton steps from that guess to full precision: 3.5e-2 → 1.8e-3 → 4.7e-6 → 3.3e-11 (quadratic).
  static constexpr int kRsqrtNewtonSteps = 3;
};
template <>
struct FloatBits<double> {
  using Word = std::uint64_t;
  static constexpr int kMantissaBits = 52;
  static constexpr Word kExponentMask = 0x7ffu;
  static constexpr Word kRsqrtMagic = 0x5fe6eb50c7b537a9u;
  static constexpr int kRsqrtNewtonSteps = 4;  // ... → 3.3e-11 → 1.1e-21
};

template <class T>
ROMP_MATH_INLINE typename FloatBits<T>::Word to_bits(T x) {
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_same_v<T, float>)
    return __float_as_uint(x);
  else
    return static_cast<std::uint64_t>(__double_as_longlong(x));
#else
  typename FloatBits<T>::Word word;
  std::memcpy(&word, &x, sizeof word);
  return word;
#endif
}

template <class T>
ROMP_MATH_INLINE T from_bits(typename FloatBits<T>::Word word) {
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_same_v<T, float>)
    return __uint_as_float(word);
  else
    return __longlong_as_double(static_cast<long long>(word));
#else
  T x;
  std::memcpy(&x, &word, sizeof x);
  return x;
#endif
}

}  // namespace detail

// condition ? if_true : if_false, with both arguments already evaluated. Never a branch.
template <class T>
ROMP_MATH_INLINE T select(bool condition, T if_true, T if_false) {
#if defined(__CUDA_ARCH__)
  return condition ? if_true : if_false;
#else
  if constexpr (std::is_floating_point_v<T>) {
    using Word = typename detail::FloatBits<T>::Word;
    const Word mask = Word(0) - Word(condition);
    return detail::from_bits<T>((detail::to_bits(if_true) & mask) | (detail::to_bits(if_false) & ~mask));
  } else {
    return condition ? if_true : if_false;
  }
#endif
}

template <class T>
ROMP_MATH_INLINE T abs(T x) {
  return select(x < T(0), -x, x);
}

template <class T>
ROMP_MATH_INLINE T min(T a, T b) {
  return select(b < a, b, a);
}

template <class T>
ROMP_MATH_INLINE T max(T a, T b) {
  return select(a < b, b, a);
}

// x / |x| with sign(0) = +1: the convention every sign-carrying formula in romp relies on.
template <class T>
ROMP_MATH_INLINE T sign(T x) {
  return select(x < T(0), T(-1), T(1));
}

// Exchanges a and b when `condition` holds.
template <class T>
ROMP_MATH_INLINE void swap_if(bool condition, T& a, T& b) {
  const T old_a = a;
  a = select(condition, b, a);
  b = select(condition, old_a, b);
}

// 1/√x for x ≥ 0 (+inf or a huge finite value at 0). Device: the hardware approximation (rsqrtf: one
// MUFU.RSQ, ≤ 2 ulp). Host: Newton-Raphson y ← y (3 - x y²)/2 from the bit-level guess, which ends
// within a few ulp of the correctly rounded value; the tests' bounds are checked on this path.
template <class T>
ROMP_MATH_INLINE T rsqrt(T x) {
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_same_v<T, float>)
    return ::rsqrtf(x);
  else
    return ::rsqrt(x);
#else
  using Bits = detail::FloatBits<T>;
  T y = detail::from_bits<T>(Bits::kRsqrtMagic - (detail::to_bits(x) >> 1));
  const T half_x = T(0.5) * x;
  for (int step = 0; step < Bits::kRsqrtNewtonSteps; ++step) y = y * (T(1.5) - half_x * y * y);
  return y;
#endif
}

// √x for x ≥ 0. Host: x · rsqrt(x), exactly 0 at 0 (the host rsqrt stays finite there).
template <class T>
ROMP_MATH_INLINE T sqrt(T x) {
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_same_v<T, float>)
    return ::sqrtf(x);
  else
    return ::sqrt(x);
#else
  return x * rsqrt(x);
#endif
}

// A power of two 2^k near a non-negative x, as the pair (down = 2^-k, up = 2^k): x down lies in
// [1, 2) for normal x, multiplying by either factor is exact, and both factors are normal numbers.
// Read from the exponent field (a few integer instructions; std::frexp/ldexp are library calls).
// k is clamped to [1 - bias, bias - 1]: denormal x get the smallest normal exponent (x down < 1)
// and x near the largest finite value k = bias - 1 (x down < 4), so that 2^-k stays normal.
template <class T>
struct PowerOfTwoScale {
  T down;
  T up;
};

template <class T>
ROMP_MATH_INLINE PowerOfTwoScale<T> power_of_two_scale(T x) {
  using Bits = detail::FloatBits<T>;
  using Word = typename Bits::Word;
  const Word biased = (detail::to_bits(x) >> Bits::kMantissaBits) & Bits::kExponentMask;
  const Word clamped = max(Word(1), min(biased, Word(Bits::kExponentMask - 2)));
  // 2^-k has the biased exponent 2 bias - biased = (kExponentMask - 1) - biased.
  return {detail::from_bits<T>((Bits::kExponentMask - 1 - clamped) << Bits::kMantissaBits),
          detail::from_bits<T>(clamped << Bits::kMantissaBits)};
}

}  // namespace romp::math
