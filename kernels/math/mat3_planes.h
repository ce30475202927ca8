// Mat3Planes<T>, Vec3Planes<T>: views of the engine's structure-of-arrays layout for 3x3 matrices and 3-vectors.
//
// Component-major planes: entry (r, c) of matrix i is data[(3 r + c) count + i], component k of
// vector i is data[k count + i]. Consecutive threads (or SIMD lanes) touch consecutive addresses in
// every plane, so loads and stores stay coalesced. The views never own memory.
#pragma once

#include <type_traits>

#include "kernels/core/hd.h"
#include "kernels/math/mat3.h"
#include "kernels/math/scalar.h"
#include "kernels/math/vec3.h"

namespace romp {

template <class T>
class Mat3Planes {
 public:
  using value_type = std::remove_cv_t<T>;
  static constexpr int kPlanes = 9;

  Mat3Planes() = default;
  ROMP_HD Mat3Planes(T* data, Index count) : data_(data), count_(count) {}
  // Mat3Planes<T> converts to Mat3Planes<const T>, never the other way.
  template <class U, class = std::enable_if_t<std::is_convertible_v<U (*)[], T (*)[]>>>
  ROMP_HD Mat3Planes(const Mat3Planes<U>& other) : data_(other.data()), count_(other.count()) {}

  ROMP_MATH_INLINE Mat3<value_type> load(Index i) const {
    Mat3<value_type> a;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) a.m[r][c] = data_[(3 * r + c) * count_ + i];
    return a;
  }
  ROMP_MATH_INLINE void store(Index i, const Mat3<value_type>& a) const {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) data_[(3 * r + c) * count_ + i] = a.m[r][c];
  }

  ROMP_HD T* data() const { return data_; }
  // Number of matrices (each plane holds `count` scalars; the view spans 9 count).
  ROMP_HD Index count() const { return count_; }

 private:
  T* data_ = nullptr;
  Index count_ = 0;
};

template <class T>
class Vec3Planes {
 public:
  using value_type = std::remove_cv_t<T>;
  static constexpr int kPlanes = 3;

  Vec3Planes() = default;
  ROMP_HD Vec3Planes(T* data, Index count) : data_(data), count_(count) {}
  template <class U, class = std::enable_if_t<std::is_convertible_v<U (*)[], T (*)[]>>>
  ROMP_HD Vec3Planes(const Vec3Planes<U>& other) : data_(other.data()), count_(other.count()) {}

  ROMP_MATH_INLINE Vec3<value_type> load(Index i) const {
    return Vec3<value_type>(data_[i], data_[count_ + i], data_[2 * count_ + i]);
  }
  ROMP_MATH_INLINE void store(Index i, const Vec3<value_type>& x) const {
    for (int k = 0; k < 3; ++k) data_[k * count_ + i] = x[k];
  }

  ROMP_HD T* data() const { return data_; }
  ROMP_HD Index count() const { return count_; }

 private:
  T* data_ = nullptr;
  Index count_ = 0;
};

}  // namespace romp
