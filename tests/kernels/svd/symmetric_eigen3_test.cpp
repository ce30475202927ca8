// symmetric_eigen3 reconstructs symmetric matrices of every sign pattern, and positive_semidefinite_part
// is the projection onto the semidefinite cone (and the identity on it).
#include <gtest/gtest.h>

#include <vector>

#include "kernels/math/mat3.h"
#include "kernels/svd/symmetric_eigen3.h"
#include "tests/kernels/svd/svd_test_matrices.h"

namespace romp {
namespace {

using M = Mat3<double>;

constexpr int kSamples = 2000;

// Q diag(λ) Qᵀ with a random rotation Q and the given eigenvalues.
M symmetric_with_eigenvalues(test::MatrixSampler& sampler, double l0, double l1, double l2) {
  const M Q = sampler.rotation();
  return Q * times_transpose(M::diag(l0, l1, l2), Q);
}

// Eigenvalues of random sign and magnitude over three decades, some repeated, some zero.
std::vector<M> symmetric_samples(test::MatrixSampler& sampler) {
  std::vector<M> samples = {M::zero(), M::identity(), M::diag(-1, 2, -3), M::diag(4, 4, -4)};
  for (int i = 0; i < kSamples; ++i) {
    const double a = sampler.random_sign() * sampler.log_uniform(1e-2, 1e1);
    const double b = sampler.random_sign() * sampler.log_uniform(1e-2, 1e1);
    const double c = i % 4 == 0 ? a : i % 4 == 1 ? 0.0 : sampler.random_sign() * sampler.log_uniform(1e-2, 1e1);
    samples.push_back(symmetric_with_eigenvalues(sampler, a, b, c) * sampler.log_uniform(1e-3, 1e7));
  }
  return samples;
}

TEST(SymmetricEigen3, ReconstructsInDoubleAndFloat) {
  test::MatrixSampler sampler(5);
  for (const M& S : symmetric_samples(sampler)) {
    const double scale = max_abs(S) > 0 ? max_abs(S) : 1.0;
    const SymmetricEigen3<double> e = symmetric_eigen3(S);
    EXPECT_LE(max_abs(e.Q * times_transpose(M::diag(e.values), e.Q) - S), 1e-12 * scale);
    EXPECT_LE(max_abs(transpose_times(e.Q, e.Q) - M::identity()), 1e-12);
    EXPECT_NEAR(determinant(e.Q), 1.0, 1e-12);

    Mat3<float> S_float;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) S_float(r, c) = float(S(r, c));
    const SymmetricEigen3<float> f = symmetric_eigen3(S_float);
    EXPECT_LE(max_abs(f.Q * times_transpose(Mat3<float>::diag(f.values), f.Q) - S_float), 1e-5f * float(scale));
  }
}

TEST(SymmetricEigen3, SemidefinitePartLeavesSemidefiniteMatricesUnchanged) {
  test::MatrixSampler sampler(7);
  for (int i = 0; i < kSamples; ++i) {
    const M S = symmetric_with_eigenvalues(sampler, sampler.uniform(0, 5), sampler.uniform(0, 5), i % 2 ? 0.0 : 1.0);
    const SymmetricEigen3<double> e = symmetric_eigen3(S);
    // Rounding can leave a zero eigenvalue at -1e-16: only inputs the test can call definite count.
    if (e.values[0] < 0 || e.values[1] < 0 || e.values[2] < 0) continue;
    EXPECT_EQ(positive_semidefinite_part(S), S);
  }
}

// S₊ is the projection of S onto the semidefinite cone exactly when S₊ ⪰ 0, S − S₊ ⪯ 0 and
// S₊ (S − S₊) = 0 (the two parts live on orthogonal eigenspaces).
TEST(SymmetricEigen3, SemidefinitePartIsTheProjectionOntoTheCone) {
  test::MatrixSampler sampler(11);
  for (const M& S : symmetric_samples(sampler)) {
    const double scale = max_abs(S) > 0 ? max_abs(S) : 1.0;
    const M S_plus = positive_semidefinite_part(S);
    const SymmetricEigen3<double> plus = symmetric_eigen3(S_plus);
    const SymmetricEigen3<double> minus = symmetric_eigen3(S - S_plus);
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(plus.values[k], -1e-12 * scale);
      EXPECT_LE(minus.values[k], 1e-12 * scale);
    }
    EXPECT_LE(max_abs(S_plus * (S - S_plus)), 1e-12 * scale * scale);
  }
}

}  // namespace
}  // namespace romp
