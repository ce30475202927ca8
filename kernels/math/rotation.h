// Rotations from a rotation vector (axis times angle), by Rodrigues' formula.
#pragma once

#include <cmath>

#include "kernels/core/hd.h"
#include "kernels/math/mat3.h"

namespace romp {

// exp([θ]×) for θ = axis × angle: the rotation by |θ| about θ/|θ|.
template <class T>
ROMP_HD Mat3<T> rotation_from_vector(const Vec3<T>& theta) {
  const T angle = norm(theta);
  if (angle == T(0)) return Mat3<T>::identity();
  const Vec3<T> k = theta * (T(1) / angle);
  const Mat3<T> K(T(0), -k[2], k[1], k[2], T(0), -k[0], -k[1], k[0], T(0));
  return Mat3<T>::identity() + std::sin(angle) * K + (T(1) - std::cos(angle)) * (K * K);
}

}  // namespace romp
