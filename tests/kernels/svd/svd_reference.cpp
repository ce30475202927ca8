// Eigen's double-precision JacobiSVD as the reference for svd3: signed singular values.
#include "tests/kernels/svd/svd_reference.h"

#include <Eigen/Dense>

namespace romp::test {

Vec3<double> reference_signed_singular_values(const Mat3<double>& F) {
  Eigen::Matrix3d matrix;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) matrix(r, c) = F(r, c);
  const Eigen::Vector3d sigma = Eigen::JacobiSVD<Eigen::Matrix3d>(matrix).singularValues();
  const double sign_of_det = matrix.determinant() < 0.0 ? -1.0 : 1.0;
  return Vec3<double>(sigma(0), sigma(1), sign_of_det * sigma(2));
}

}  // namespace romp::test
