// e^x and erf(x) that vectorise on the host, for the GELU of the neural constitutive laws.
//
// In a SIMD loop over particles (simd_for_each), a libm call keeps the whole loop scalar: without
// -ffast-math glibc declares no vector variants. So the float versions here are branch-free polynomials
// in plain arithmetic and bit operations, which the compiler vectorises like the rest of the loop body:
//   exp: x = n ln 2 + r with n = round(x / ln 2) (the 1.5·2²³ rounding trick), |r| ≤ ln 2 / 2, e^r by its
//        Taylor polynomial of degree 7 (remainder < 6e-10), 2^n from the exponent bits. Relative error
//        ≤ 2 ulp; x is clamped to [-87, 88], where 2^n stays a normal float.
//   erf: Abramowitz & Stegun 7.1.26, |error| ≤ 1.5e-7 in exact arithmetic (LibTorch's vectorised CPU erf is
//        the same formula), and its Taylor series below |x| = 0.8, where the formula loses digits to
//        cancellation; erf(0) = 0, and in float |error| ≤ 3e-7 (worst measured 2.48e-7 at x = 0.84;
//        tests/kernels/math/exp_erf_test.cpp).
// On the device float uses CUDA's expf and erff; double uses the standard library on both (double runs
// check gradients, where the last bits matter more than speed).
#pragma once

#include <cmath>
#include <cstdint>
#include <type_traits>

#include "kernels/math/scalar.h"

namespace romp::math {

template <class T>
ROMP_MATH_INLINE T exp(T x) {
  if constexpr (!std::is_same_v<T, float>) {
    return std::exp(x);
  } else {
#if defined(__CUDA_ARCH__)
    return ::expf(x);
#else
    const float clamped = min(max(x, -87.0f), 88.0f);
    constexpr float kRound = 12582912.0f;  // 1.5 · 2²³: adding it rounds to an integer held in the low bits
    const float shifted = clamped * 1.44269504088896341f + kRound;
    const float n = shifted - kRound;
    const std::int32_t exponent = std::int32_t(detail::to_bits(shifted) - detail::to_bits(kRound));
    const float r = (clamped - n * 0.693145751953125f) - n * 1.428606765330187e-06f;  // ln 2 in two parts
    float p = 1.0f / 5040.0f;
    p = p * r + 1.0f / 720.0f;
    p = p * r + 1.0f / 120.0f;
    p = p * r + 1.0f / 24.0f;
    p = p * r + 1.0f / 6.0f;
    p = p * r + 0.5f;
    p = p * r + 1.0f;
    p = p * r + 1.0f;
    return p * detail::from_bits<float>(std::uint32_t(exponent + 127) << 23);
#endif
  }
}

template <class T>
ROMP_MATH_INLINE T erf(T x) {
  if constexpr (!std::is_same_v<T, float>) {
    return std::erf(x);
  } else {
#if defined(__CUDA_ARCH__)
    return ::erff(x);
#else
    const float a = abs(x);
    const float t = 1.0f / (1.0f + 0.3275911f * a);
    float p = 1.061405429f;
    p = p * t - 1.453152027f;
    p = p * t + 1.421413741f;
    p = p * t - 0.284496736f;
    p = p * t + 0.254829592f;
    const float far = 1.0f - p * t * exp(-a * a);
    // Near 0 the formula's 1 − (≈ 1) cancels (5e-7 off at |x| = 0.01, 3e-7 at 0.5 in float): there, the
    // Taylor series 2/√π Σ (−1)ⁿ x²ⁿ⁺¹ / (n! (2n + 1)) to x¹⁹ (remainder < 2e-10 for |x| ≤ 0.8).
    const float s = a * a;
    float q = -1.0f / 6894720.0f;
    q = q * s + 1.0f / 685440.0f;
    q = q * s - 1.0f / 75600.0f;
    q = q * s + 1.0f / 9360.0f;
    q = q * s - 1.0f / 1320.0f;
    q = q * s + 1.0f / 216.0f;
    q = q * s - 1.0f / 42.0f;
    q = q * s + 1.0f / 10.0f;
    q = q * s - 1.0f / 3.0f;
    q = q * s + 1.0f;
    const float near = 1.12837916709551257f * a * q;
    const float magnitude = select(a < 0.8f, near, far);
    return select(x < 0.0f, -magnitude, magnitude);
#endif
  }
}

}  // namespace romp::math
