// Eigen-decomposition of a symmetric 3x3 matrix, and its projection onto the positive semidefinite cone.
//
// The decomposition is step 1 of svd3 (svd3.h) applied to S itself rather than to AᵀA: cyclic Jacobi
// sweeps with the approximate Givens conjugations of McAdams et al. 2011, accumulated as a
// quaternion, after the same exact power-of-two normalisation. Jacobi converges for every
// symmetric matrix, definite or not, so the sweep counts of Svd3Config carry over. Branch-free
// like svd3, so a warp never diverges.
#pragma once

#include "kernels/math/mat3.h"
#include "kernels/math/scalar.h"
#include "kernels/math/vec3.h"
#include "kernels/svd/svd3.h"

namespace romp {

template <class T>
struct SymmetricEigen3 {
  Mat3<T> Q;       // proper rotation whose columns are the eigenvectors
  Vec3<T> values;  // eigenvalues, unordered: S = Q diag(values) Qᵀ
};

// S = Q diag(λ) Qᵀ; only the upper triangle's mirror is assumed, i.e. S must be symmetric.
template <class T>
ROMP_MATH_INLINE SymmetricEigen3<T> symmetric_eigen3(const Mat3<T>& S) {
  const math::PowerOfTwoScale<T> scale = math::power_of_two_scale(max_abs(S));
  Mat3<T> A = S * scale.down;
  svd_detail::Quaternion<T> rotation{T(1), {T(0), T(0), T(0)}};
  svd_detail::jacobi_sweeps<Svd3Config<T>::kJacobiSweeps>(A, rotation);
  return {svd_detail::rotation_matrix(rotation), diagonal(A) * scale.up};
}

// The nearest positive semidefinite matrix to a symmetric S (in the Frobenius norm): its negative
// eigenvalues set to zero. S itself, bit for bit, when no eigenvalue is negative, so a projection
// that has nothing to do changes nothing.
template <class T>
ROMP_MATH_INLINE Mat3<T> positive_semidefinite_part(const Mat3<T>& S) {
  const SymmetricEigen3<T> eigen = symmetric_eigen3(S);
  const Vec3<T>& values = eigen.values;
  const bool definite = !(values[0] < T(0)) && !(values[1] < T(0)) && !(values[2] < T(0));
  const Vec3<T> clamped(math::max(values[0], T(0)), math::max(values[1], T(0)), math::max(values[2], T(0)));
  const Mat3<T> projected = eigen.Q * times_transpose(Mat3<T>::diag(clamped), eigen.Q);
  Mat3<T> result;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) result(r, c) = math::select(definite, S(r, c), projected(r, c));
  return result;
}

}  // namespace romp
