// Eigen's double-precision JacobiSVD, the reference of the svd3 tests (compiled as C++, never by nvcc).
#pragma once

#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"

namespace romp::test {

// Singular values of F from Eigen::JacobiSVD<Matrix3d>, descending, with the smallest negated when
// det F < 0: the values svd3 promises for F.
Vec3<double> reference_signed_singular_values(const Mat3<double>& F);

}  // namespace romp::test
