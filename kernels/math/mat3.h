// Mat3<T>: a row-major 3x3 matrix value type for single-source kernels (host and device).
#pragma once

#include "kernels/core/hd.h"
#include "kernels/math/scalar.h"
#include "kernels/math/vec3.h"

namespace romp {

template <class T>
struct Mat3 {
  T m[3][3];  // m[row][column]

  Mat3() = default;  // trivial: uninitialised, like a scalar
  // Entries in row-major order, as the matrix is written on paper.
  ROMP_HD constexpr Mat3(T m00, T m01, T m02, T m10, T m11, T m12, T m20, T m21, T m22)
      : m{{m00, m01, m02}, {m10, m11, m12}, {m20, m21, m22}} {}

  ROMP_HD static constexpr Mat3 zero() { return diag(T(0), T(0), T(0)); }
  ROMP_HD static constexpr Mat3 identity() { return diag(T(1), T(1), T(1)); }
  ROMP_HD static constexpr Mat3 diag(T d0, T d1, T d2) { return Mat3(d0, T(0), T(0), T(0), d1, T(0), T(0), T(0), d2); }
  ROMP_HD static constexpr Mat3 diag(const Vec3<T>& d) { return diag(d[0], d[1], d[2]); }
  ROMP_HD static constexpr Mat3 from_rows(const Vec3<T>& r0, const Vec3<T>& r1, const Vec3<T>& r2) {
    return Mat3(r0[0], r0[1], r0[2], r1[0], r1[1], r1[2], r2[0], r2[1], r2[2]);
  }
  ROMP_HD static constexpr Mat3 from_columns(const Vec3<T>& c0, const Vec3<T>& c1, const Vec3<T>& c2) {
    return Mat3(c0[0], c1[0], c2[0], c0[1], c1[1], c2[1], c0[2], c1[2], c2[2]);
  }
  // a bᵀ
  ROMP_HD static constexpr Mat3 outer(const Vec3<T>& a, const Vec3<T>& b) {
    return Mat3(a[0] * b[0], a[0] * b[1], a[0] * b[2], a[1] * b[0], a[1] * b[1], a[1] * b[2], a[2] * b[0], a[2] * b[1],
                a[2] * b[2]);
  }

  ROMP_HD constexpr T& operator()(int row, int column) { return m[row][column]; }
  ROMP_HD constexpr const T& operator()(int row, int column) const { return m[row][column]; }

  ROMP_HD constexpr Vec3<T> row(int r) const { return Vec3<T>(m[r][0], m[r][1], m[r][2]); }
  ROMP_HD constexpr Vec3<T> column(int c) const { return Vec3<T>(m[0][c], m[1][c], m[2][c]); }
  ROMP_MATH_INLINE void set_column(int c, const Vec3<T>& value) {
    for (int r = 0; r < 3; ++r) m[r][c] = value[r];
  }

  ROMP_MATH_INLINE Mat3& operator+=(const Mat3& b) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m[r][c] += b.m[r][c];
    return *this;
  }
  ROMP_MATH_INLINE Mat3& operator-=(const Mat3& b) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m[r][c] -= b.m[r][c];
    return *this;
  }
  ROMP_MATH_INLINE Mat3& operator*=(T s) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m[r][c] *= s;
    return *this;
  }
};

template <class T>
ROMP_MATH_INLINE Mat3<T> operator+(Mat3<T> a, const Mat3<T>& b) {
  return a += b;
}
template <class T>
ROMP_MATH_INLINE Mat3<T> operator-(Mat3<T> a, const Mat3<T>& b) {
  return a -= b;
}
template <class T>
ROMP_MATH_INLINE Mat3<T> operator-(Mat3<T> a) {
  return a *= T(-1);
}
template <class T>
ROMP_MATH_INLINE Mat3<T> operator*(Mat3<T> a, T s) {
  return a *= s;
}
template <class T>
ROMP_MATH_INLINE Mat3<T> operator*(T s, Mat3<T> a) {
  return a *= s;
}
template <class T>
ROMP_MATH_INLINE bool operator==(const Mat3<T>& a, const Mat3<T>& b) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (!(a.m[r][c] == b.m[r][c])) return false;
  return true;
}

template <class T>
ROMP_MATH_INLINE Mat3<T> operator*(const Mat3<T>& a, const Mat3<T>& b) {
  Mat3<T> p;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) p.m[r][c] = a.m[r][0] * b.m[0][c] + a.m[r][1] * b.m[1][c] + a.m[r][2] * b.m[2][c];
  return p;
}
template <class T>
ROMP_MATH_INLINE Vec3<T> operator*(const Mat3<T>& a, const Vec3<T>& x) {
  return Vec3<T>(dot(a.row(0), x), dot(a.row(1), x), dot(a.row(2), x));
}

template <class T>
ROMP_MATH_INLINE Mat3<T> transpose(const Mat3<T>& a) {
  return Mat3<T>::from_columns(a.row(0), a.row(1), a.row(2));
}
// aᵀ b without forming the transpose.
template <class T>
ROMP_MATH_INLINE Mat3<T> transpose_times(const Mat3<T>& a, const Mat3<T>& b) {
  Mat3<T> p;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) p.m[r][c] = a.m[0][r] * b.m[0][c] + a.m[1][r] * b.m[1][c] + a.m[2][r] * b.m[2][c];
  return p;
}
// a bᵀ without forming the transpose.
template <class T>
ROMP_MATH_INLINE Mat3<T> times_transpose(const Mat3<T>& a, const Mat3<T>& b) {
  Mat3<T> p;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) p.m[r][c] = a.m[r][0] * b.m[c][0] + a.m[r][1] * b.m[c][1] + a.m[r][2] * b.m[c][2];
  return p;
}

template <class T>
ROMP_MATH_INLINE T trace(const Mat3<T>& a) {
  return a.m[0][0] + a.m[1][1] + a.m[2][2];
}
template <class T>
ROMP_MATH_INLINE T determinant(const Mat3<T>& a) {
  return dot(a.row(0), cross(a.row(1), a.row(2)));
}
// x = a⁻¹ r by Cramer's rule (the columns of det(a) a⁻¹ are the cross products of a's rows), where
// det a > 0; returns false, leaving x alone, for an inverted or degenerate a (or a non-finite det).
template <class T>
ROMP_MATH_INLINE bool solve_where_positive(const Mat3<T>& a, const Vec3<T>& r, Vec3<T>& x) {
  const Vec3<T> r0 = a.row(0), r1 = a.row(1), r2 = a.row(2);
  const T det = dot(r0, cross(r1, r2));
  if (!(det > T(0))) return false;
  x = (r[0] * cross(r1, r2) + r[1] * cross(r2, r0) + r[2] * cross(r0, r1)) * (T(1) / det);
  return true;
}
// Σ a_ij b_ij, the Frobenius inner product (a double contraction a : b).
template <class T>
ROMP_MATH_INLINE T inner(const Mat3<T>& a, const Mat3<T>& b) {
  T sum = T(0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) sum += a.m[r][c] * b.m[r][c];
  return sum;
}
template <class T>
ROMP_MATH_INLINE T squared_frobenius_norm(const Mat3<T>& a) {
  return inner(a, a);
}
template <class T>
ROMP_MATH_INLINE T frobenius_norm(const Mat3<T>& a) {
  return math::sqrt(squared_frobenius_norm(a));
}
// max |a_ij|
template <class T>
ROMP_MATH_INLINE T max_abs(const Mat3<T>& a) {
  T largest = T(0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) largest = math::max(largest, math::abs(a.m[r][c]));
  return largest;
}
// The diagonal as a vector.
template <class T>
ROMP_MATH_INLINE Vec3<T> diagonal(const Mat3<T>& a) {
  return Vec3<T>(a.m[0][0], a.m[1][1], a.m[2][2]);
}
// (a + aᵀ)/2 and (a − aᵀ)/2.
template <class T>
ROMP_MATH_INLINE Mat3<T> symmetric_part(const Mat3<T>& a) {
  return T(0.5) * (a + transpose(a));
}
template <class T>
ROMP_MATH_INLINE Mat3<T> skew_part(const Mat3<T>& a) {
  return T(0.5) * (a - transpose(a));
}

}  // namespace romp
