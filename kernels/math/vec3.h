// Vec3<T>: a 3-vector value type for single-source kernels (host and device), templated on the scalar.
#pragma once

#include "kernels/core/hd.h"
#include "kernels/math/scalar.h"

namespace romp {

template <class T>
struct Vec3 {
  T v[3];

  Vec3() = default;  // trivial: uninitialised, like a scalar, so arrays of Vec3 cost nothing to declare
  ROMP_HD constexpr Vec3(T x, T y, T z) : v{x, y, z} {}

  ROMP_HD static constexpr Vec3 zero() { return Vec3(T(0), T(0), T(0)); }
  ROMP_HD static constexpr Vec3 constant(T value) { return Vec3(value, value, value); }
  // The k-th unit vector.
  ROMP_HD static constexpr Vec3 unit(int k) { return Vec3(T(k == 0), T(k == 1), T(k == 2)); }

  ROMP_HD constexpr T& operator[](int k) { return v[k]; }
  ROMP_HD constexpr const T& operator[](int k) const { return v[k]; }

  ROMP_MATH_INLINE Vec3& operator+=(const Vec3& b) {
    for (int k = 0; k < 3; ++k) v[k] += b.v[k];
    return *this;
  }
  ROMP_MATH_INLINE Vec3& operator-=(const Vec3& b) {
    for (int k = 0; k < 3; ++k) v[k] -= b.v[k];
    return *this;
  }
  ROMP_MATH_INLINE Vec3& operator*=(T s) {
    for (int k = 0; k < 3; ++k) v[k] *= s;
    return *this;
  }
};

template <class T>
ROMP_MATH_INLINE Vec3<T> operator+(Vec3<T> a, const Vec3<T>& b) {
  return a += b;
}
template <class T>
ROMP_MATH_INLINE Vec3<T> operator-(Vec3<T> a, const Vec3<T>& b) {
  return a -= b;
}
template <class T>
ROMP_MATH_INLINE Vec3<T> operator-(const Vec3<T>& a) {
  return Vec3<T>(-a[0], -a[1], -a[2]);
}
template <class T>
ROMP_MATH_INLINE Vec3<T> operator*(Vec3<T> a, T s) {
  return a *= s;
}
template <class T>
ROMP_MATH_INLINE Vec3<T> operator*(T s, Vec3<T> a) {
  return a *= s;
}
template <class T>
ROMP_MATH_INLINE bool operator==(const Vec3<T>& a, const Vec3<T>& b) {
  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

// Component-wise product.
template <class T>
ROMP_MATH_INLINE Vec3<T> hadamard(const Vec3<T>& a, const Vec3<T>& b) {
  return Vec3<T>(a[0] * b[0], a[1] * b[1], a[2] * b[2]);
}
template <class T>
ROMP_MATH_INLINE T dot(const Vec3<T>& a, const Vec3<T>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class T>
ROMP_MATH_INLINE Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return Vec3<T>(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
}
template <class T>
ROMP_MATH_INLINE T squared_norm(const Vec3<T>& a) {
  return dot(a, a);
}
template <class T>
ROMP_MATH_INLINE T norm(const Vec3<T>& a) {
  return math::sqrt(squared_norm(a));
}

}  // namespace romp
