// Finiteness tests that work the same in host and device code (and are not folded away: no fast-math).
#pragma once

#include "kernels/core/hd.h"
#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"

namespace romp {

// x * 0 is 0 for every finite x and NaN for ±inf or NaN; summing these never overflows.
template <class T>
ROMP_HD_INLINE bool is_finite(T x) {
  return x * T(0) == T(0);
}
template <class T>
ROMP_HD_INLINE bool is_finite(const Vec3<T>& v) {
  return is_finite(v[0] * T(0) + v[1] * T(0) + v[2] * T(0));
}
template <class T>
ROMP_HD_INLINE bool is_finite(const Mat3<T>& a) {
  T sum = T(0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) sum += a.m[r][c] * T(0);
  return sum == T(0);
}

}  // namespace romp
