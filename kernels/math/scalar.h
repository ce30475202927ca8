// Scalar helpers for single-source kernels: the right square-root instruction per target, and selects.
//
// Device code uses the hardware reciprocal square root (rsqrtf: one MUFU.RSQ instruction, about
// 2 ulp; rsqrt for double), host code the correctly rounded 1/std::sqrt. Tests run the host path,
// so the accuracy bounds of the math built on these are checked with the exact variant; the device
// variant is checked against it by the gpu-labelled rerun of the same tests.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "kernels/core/hd.h"

namespace romp::math {

template <class T>
ROMP_HD_INLINE T sqrt(T x) {
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_same_v<T, float>) return ::sqrtf(x);
  else return ::sqrt(x);
#else
  return std::sqrt(x);
#endif
}

// 1/sqrt(x). Fast (a few ulp) on the device, exact on the host.
template <class T>
ROMP_HD_INLINE T rsqrt(T x) {
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_same_v<T, float>) return ::rsqrtf(x);  // MUFU.RSQ
  else return ::rsqrt(x);
#else
  return T(1) / std::sqrt(x);
#endif
}

template <class T>
ROMP_HD_INLINE T abs(T x) {
  return x < T(0) ? -x : x;
}

template <class T>
ROMP_HD_INLINE T min(T a, T b) {
  return b < a ? b : a;
}

template <class T>
ROMP_HD_INLINE T max(T a, T b) {
  return a < b ? b : a;
}

// x / |x| with sign(0) = +1: the convention every sign-carrying formula in romp relies on.
template <class T>
ROMP_HD_INLINE T sign(T x) {
  return x < T(0) ? T(-1) : T(1);
}

namespace detail {

// IEEE-754 layout of T: the unsigned word holding it and where its biased exponent field sits.
template <class T>
struct FloatBits;
template <>
struct FloatBits<float> {
  using Word = std::uint32_t;
  static constexpr int kMantissaBits = 23;
  static constexpr Word kExponentMask = 0xffu;  // after shifting out the mantissa
};
template <>
struct FloatBits<double> {
  using Word = std::uint64_t;
  static constexpr int kMantissaBits = 52;
  static constexpr Word kExponentMask = 0x7ffu;
};

template <class T>
ROMP_HD_INLINE typename FloatBits<T>::Word to_bits(T x) {
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_same_v<T, float>) return __float_as_uint(x);
  else return static_cast<std::uint64_t>(__double_as_longlong(x));
#else
  typename FloatBits<T>::Word word;
  std::memcpy(&word, &x, sizeof word);
  return word;
#endif
}

template <class T>
ROMP_HD_INLINE T from_bits(typename FloatBits<T>::Word word) {
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_same_v<T, float>) return __uint_as_float(word);
  else return __longlong_as_double(static_cast<long long>(word));
#else
  T x;
  std::memcpy(&x, &word, sizeof x);
  return x;
#endif
}

}  // namespace detail

// A power of two 2^k near a non-negative x, as the pair (down = 2^-k, up = 2^k), so that x down lies
// in [1, 4) for every finite x > 0 and multiplying by either factor is exact. Read from the exponent
// field, so it costs a few integer instructions and no branch (std::frexp/ldexp are library calls that
// block vectorisation). k is clamped to the normal range minus one at the top: for denormal x it is
// the smallest normal exponent (x down < 1), and for x near the largest finite value both factors
// stay normal numbers (x down < 4).
template <class T>
struct PowerOfTwoScale {
  T down;
  T up;
};

template <class T>
ROMP_HD_INLINE PowerOfTwoScale<T> power_of_two_scale(T x) {
  using Bits = detail::FloatBits<T>;
  using Word = typename Bits::Word;
  const Word biased = (detail::to_bits(x) >> Bits::kMantissaBits) & Bits::kExponentMask;
  // Biased exponents 1 .. max-1 are normal numbers; the field value `max` is inf/NaN.
  const Word clamped = max(Word(1), min(biased, Word(Bits::kExponentMask - 2)));
  // 2^-k has the biased exponent 2 bias - biased = (kExponentMask - 1) - biased.
  return {detail::from_bits<T>((Bits::kExponentMask - 1 - clamped) << Bits::kMantissaBits),
          detail::from_bits<T>(clamped << Bits::kMantissaBits)};
}

// Exchanges a and b when `condition` holds. Written as two selects so it compiles to conditional
// moves (CPU) or SEL/predicated moves (GPU), never to a branch that diverges within a warp.
template <class T>
ROMP_HD_INLINE void swap_if(bool condition, T& a, T& b) {
  const T old_a = a;
  a = condition ? b : a;
  b = condition ? old_a : b;
}

}  // namespace romp::math
