// svd3 and polar3 meet the issue's accuracy bounds on every input class, in float and double, through the
// batched launchers on the test binary's backend; the reference is Eigen's double-precision JacobiSVD.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/error.h"
#include "kernels/math/mat3.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/svd/svd3_batched.h"
#include "tests/kernels/svd/svd_reference.h"
#include "tests/kernels/svd/svd_test_matrices.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

// The issue's bounds: relative reconstruction, orthogonality, det = +1 and σ (relative to σ₀).
template <class T>
constexpr double kTolerance = 0.0;
template <>
constexpr double kTolerance<float> = 1e-5;
template <>
constexpr double kTolerance<double> = 1e-12;

// Matrices per random input class: enough to reach the rare slow-converging Jacobi starts, fast
// enough that the whole suite stays well under a second per backend.
constexpr int kSamples = 4000;

std::string describe(const Mat3<double>& a) {
  std::string text = "[";
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) text += std::to_string(a(r, c)) + (c < 2 ? ", " : r < 2 ? "; " : "]");
  return text;
}

// Host matrices as nine planes of T (the engine layout), and back.
template <class T>
std::vector<T> to_planes(const std::vector<Mat3<double>>& matrices) {
  const Index n = Index(matrices.size());
  std::vector<T> planes(9 * matrices.size());
  for (Index i = 0; i < n; ++i)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) planes[(3 * r + c) * n + i] = T(matrices[i](r, c));
  return planes;
}
template <class T>
Mat3<double> matrix_at(const std::vector<T>& planes, Index n, Index i) {
  Mat3<double> a;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a(r, c) = double(planes[(3 * r + c) * n + i]);
  return a;
}
template <class T>
Vec3<double> vector_at(const std::vector<T>& planes, Index n, Index i) {
  return Vec3<double>(double(planes[i]), double(planes[n + i]), double(planes[2 * n + i]));
}

template <class T>
struct SvdResults {
  std::vector<Mat3<double>> F;  // the inputs as T represents them, which is what the SVD saw
  std::vector<Mat3<double>> U, V;
  std::vector<Vec3<double>> sigma;
};

template <class T>
SvdResults<T> run_svd3(const Exec& exec, const std::vector<Mat3<double>>& inputs) {
  const Index n = Index(inputs.size());
  const std::vector<T> host_F = to_planes<T>(inputs);
  const DeviceBuffer<T> F = DeviceBuffer<T>::from_host(exec.backend, host_F, exec.stream);
  DeviceBuffer<T> U(exec.backend, 9 * n), sigma(exec.backend, 3 * n), V(exec.backend, 9 * n);
  svd3_batched(exec, Mat3Planes<const T>(F.data(), n), Mat3Planes<T>(U.data(), n), Vec3Planes<T>(sigma.data(), n),
               Mat3Planes<T>(V.data(), n));
  const std::vector<T> host_U = U.to_host(exec.stream), host_sigma = sigma.to_host(exec.stream),
                       host_V = V.to_host(exec.stream);
  SvdResults<T> results;
  for (Index i = 0; i < n; ++i) {
    results.F.push_back(matrix_at(host_F, n, i));
    results.U.push_back(matrix_at(host_U, n, i));
    results.sigma.push_back(vector_at(host_sigma, n, i));
    results.V.push_back(matrix_at(host_V, n, i));
  }
  return results;
}

bool is_finite(const Mat3<double>& a) { return std::isfinite(squared_frobenius_norm(a)); }
bool is_finite(const Vec3<double>& a) { return std::isfinite(squared_norm(a)); }
double orthogonality_error(const Mat3<double>& Q) {
  return frobenius_norm(transpose_times(Q, Q) - Mat3<double>::identity());
}

// Every bound of the issue for every matrix of a class; the first failure names the matrix.
template <class T>
void expect_accurate_svd(const std::string& input_class, const std::vector<Mat3<double>>& inputs) {
  const double tolerance = kTolerance<T>;
  const SvdResults<T> results = run_svd3<T>(test::exec(), inputs);
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const Mat3<double>& F = results.F[i];
    const Mat3<double>& U = results.U[i];
    const Mat3<double>& V = results.V[i];
    const Vec3<double>& sigma = results.sigma[i];
    const std::string where = input_class + " #" + std::to_string(i) + " F = " + describe(F);
    ASSERT_TRUE(is_finite(U) && is_finite(V) && is_finite(sigma)) << where;

    const Mat3<double> reconstruction = times_transpose(U * Mat3<double>::diag(sigma), V);
    ASSERT_LE(frobenius_norm(reconstruction - F), tolerance * frobenius_norm(F)) << where;
    ASSERT_LE(orthogonality_error(U), tolerance) << where;
    ASSERT_LE(orthogonality_error(V), tolerance) << where;
    ASSERT_NEAR(determinant(U), 1.0, tolerance) << where;
    ASSERT_NEAR(determinant(V), 1.0, tolerance) << where;

    ASSERT_GE(sigma[0], sigma[1]) << where;
    ASSERT_GE(sigma[1], std::abs(sigma[2])) << where;
    const Vec3<double> reference = test::reference_signed_singular_values(F);
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(sigma[k], reference[k], tolerance * reference[0]) << where << " σ" << k;
  }
}

std::vector<Mat3<double>> sample(int count, const std::function<Mat3<double>()>& generate) {
  std::vector<Mat3<double>> matrices;
  for (int i = 0; i < count; ++i) matrices.push_back(generate());
  return matrices;
}

template <class T>
class Svd3Accuracy : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Svd3Accuracy, Scalars);

TYPED_TEST(Svd3Accuracy, RandomMatricesWithLogUniformSingularValues) {
  test::MatrixSampler sampler(1);
  expect_accurate_svd<TypeParam>("log-uniform σ in [1e-4, 1e4]", sample(kSamples, [&] {
                                   return sampler.with_singular_values(
                                       sampler.log_uniform(1e-4, 1e4), sampler.log_uniform(1e-4, 1e4),
                                       sampler.random_sign() * sampler.log_uniform(1e-4, 1e4));
                                 }));
}

TYPED_TEST(Svd3Accuracy, GaussianMatrices) {
  test::MatrixSampler sampler(2);
  expect_accurate_svd<TypeParam>("gaussian", sample(kSamples, [&] { return sampler.gaussian(); }));
}

TYPED_TEST(Svd3Accuracy, Rotations) {
  test::MatrixSampler sampler(3);
  expect_accurate_svd<TypeParam>("rotation", sample(kSamples, [&] { return sampler.rotation(); }));
}

TYPED_TEST(Svd3Accuracy, IdentityAndItsMultiples) {
  expect_accurate_svd<TypeParam>("identity", {Mat3<double>::identity(), 3.0 * Mat3<double>::identity(),
                                              -Mat3<double>::identity(), 1e-3 * Mat3<double>::identity()});
}

TYPED_TEST(Svd3Accuracy, DiagonalMatricesOfAnySignAndOrder) {
  test::MatrixSampler sampler(4);
  expect_accurate_svd<TypeParam>("diagonal", sample(kSamples, [&] {
                                   return Mat3<double>::diag(sampler.uniform(-2, 2), sampler.uniform(-2, 2),
                                                             sampler.uniform(-2, 2));
                                 }));
}

TYPED_TEST(Svd3Accuracy, ExactlyRepeatedSingularValues) {
  test::MatrixSampler sampler(5);
  expect_accurate_svd<TypeParam>("exactly repeated", sample(kSamples, [&] {
                                   const double a = sampler.uniform(0.1, 2), b = sampler.uniform(0.1, 2);
                                   switch (int(sampler.uniform(0, 3))) {
                                     case 0: return sampler.with_singular_values(a, a, b);
                                     case 1: return sampler.with_singular_values(a, b, b);
                                     default: return sampler.with_singular_values(a, a, a);
                                   }
                                 }));
  expect_accurate_svd<TypeParam>(
      "exactly repeated, diagonal",
      {Mat3<double>::diag(2, 2, 1), Mat3<double>::diag(1, 2, 2), Mat3<double>::diag(2, 1, 2)});
}

TYPED_TEST(Svd3Accuracy, NearlyRepeatedSingularValues) {
  test::MatrixSampler sampler(6);
  expect_accurate_svd<TypeParam>("nearly repeated", sample(kSamples, [&] {
                                   const double a = sampler.uniform(0.1, 2);
                                   return sampler.with_singular_values(a, a * (1 + sampler.log_uniform(1e-9, 1e-3)),
                                                                       a * (1 - sampler.log_uniform(1e-9, 1e-3)));
                                 }));
}

TYPED_TEST(Svd3Accuracy, RankTwoOneAndZero) {
  test::MatrixSampler sampler(7);
  expect_accurate_svd<TypeParam>("rank 2", sample(kSamples, [&] {
                                   return sampler.with_singular_values(sampler.uniform(0.1, 2), sampler.uniform(0.1, 2),
                                                                       0);
                                 }));
  expect_accurate_svd<TypeParam>(
      "rank 1", sample(kSamples, [&] { return sampler.with_singular_values(sampler.uniform(0.1, 2), 0, 0); }));
  expect_accurate_svd<TypeParam>("rank 0", {Mat3<double>::zero()});
}

TYPED_TEST(Svd3Accuracy, InvertedMatrixCarriesSignInSmallestSingularValue) {
  test::MatrixSampler sampler(8);
  const std::vector<Mat3<double>> inverted = sample(kSamples, [&] {
    return sampler.with_singular_values(sampler.uniform(0.1, 2), sampler.uniform(0.1, 2), -sampler.uniform(0.1, 2));
  });
  expect_accurate_svd<TypeParam>("inverted", inverted);
  const SvdResults<TypeParam> results = run_svd3<TypeParam>(test::exec(), inverted);
  for (std::size_t i = 0; i < inverted.size(); ++i) {
    ASSERT_LT(results.sigma[i][2], 0.0) << describe(results.F[i]);
    ASSERT_GT(results.sigma[i][1], 0.0) << describe(results.F[i]);
  }
}

TYPED_TEST(Svd3Accuracy, NearlyFlatElement) {
  test::MatrixSampler sampler(9);
  expect_accurate_svd<TypeParam>("σ₂ = ±1e-7", sample(kSamples, [&] {
                                   return sampler.with_singular_values(sampler.uniform(0.5, 2), sampler.uniform(0.5, 2),
                                                                       sampler.random_sign() * 1e-7);
                                 }));
}

TYPED_TEST(Svd3Accuracy, ConditionNumber1e8) {
  test::MatrixSampler sampler(10);
  expect_accurate_svd<TypeParam>("condition 1e8", sample(kSamples, [&] {
                                   return sampler.with_singular_values(1.0, sampler.log_uniform(1e-8, 1.0), 1e-8);
                                 }));
}

TYPED_TEST(Svd3Accuracy, VeryLargeAndVerySmallScales) {
  test::MatrixSampler sampler(11);
  for (double scale : {1e15, 1e-15}) {
    expect_accurate_svd<TypeParam>("scale " + std::to_string(scale), sample(kSamples, [&] {
                                     return scale * sampler.with_singular_values(
                                                        sampler.log_uniform(1e-2, 1e2), sampler.log_uniform(1e-2, 1e2),
                                                        sampler.random_sign() * sampler.log_uniform(1e-2, 1e2));
                                   }));
  }
}

template <class T>
class Polar3Accuracy : public ::testing::Test {};
TYPED_TEST_SUITE(Polar3Accuracy, Scalars);

TYPED_TEST(Polar3Accuracy, RotationTimesSymmetricStretchReconstructsF) {
  using T = TypeParam;
  const double tolerance = kTolerance<T>;
  test::MatrixSampler sampler(12);
  // Generic, inverted and repeated-σ inputs.
  const std::vector<Mat3<double>> inputs = sample(kSamples, [&] {
    const double a = sampler.log_uniform(1e-2, 1e2);
    switch (int(sampler.uniform(0, 3))) {
      case 0: return sampler.gaussian();
      case 1: return sampler.with_singular_values(a, sampler.log_uniform(1e-2, 1e2), -sampler.log_uniform(1e-2, 1e2));
      default: return sampler.with_singular_values(a, a, sampler.log_uniform(1e-2, 1e2));
    }
  });
  const Exec& exec = test::exec();
  const Index n = Index(inputs.size());
  const std::vector<T> host_F = to_planes<T>(inputs);
  const DeviceBuffer<T> F = DeviceBuffer<T>::from_host(exec.backend, host_F, exec.stream);
  DeviceBuffer<T> R(exec.backend, 9 * n), S(exec.backend, 9 * n);
  polar3_batched(exec, Mat3Planes<const T>(F.data(), n), Mat3Planes<T>(R.data(), n), Mat3Planes<T>(S.data(), n));
  const std::vector<T> host_R = R.to_host(exec.stream), host_S = S.to_host(exec.stream);
  for (Index i = 0; i < n; ++i) {
    const Mat3<double> f = matrix_at(host_F, n, i), r = matrix_at(host_R, n, i), s = matrix_at(host_S, n, i);
    const std::string where = "#" + std::to_string(i) + " F = " + describe(f);
    ASSERT_LE(frobenius_norm(r * s - f), tolerance * frobenius_norm(f)) << where;
    ASSERT_LE(orthogonality_error(r), tolerance) << where;
    ASSERT_NEAR(determinant(r), 1.0, tolerance) << where;
    ASSERT_LE(frobenius_norm(s - transpose(s)), tolerance * frobenius_norm(f)) << where;
    // S carries the sign of det F: its determinant has the sign of det F (inverted → indefinite S).
    if (std::abs(determinant(f)) > 1e-3 * std::pow(frobenius_norm(f), 3))
      ASSERT_EQ(determinant(s) < 0, determinant(f) < 0) << where;
  }
}

TEST(Svd3Batched, SameBitsForEveryCpuThreadCount) {
  test::MatrixSampler sampler(13);
  // Not a multiple of any SIMD width or chunk size, so partial chunks are covered.
  const std::vector<Mat3<double>> inputs = sample(1001, [&] { return sampler.gaussian(); });
  const SvdResults<float> one_thread = run_svd3<float>(test::exec_with_threads(1), inputs);
  for (int threads : {2, 3}) {
    const SvdResults<float> many = run_svd3<float>(test::exec_with_threads(threads), inputs);
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      ASSERT_TRUE(many.U[i] == one_thread.U[i] && many.V[i] == one_thread.V[i] && many.sigma[i] == one_thread.sigma[i])
          << "threads " << threads << " #" << i;
    }
  }
}

TEST(Svd3Batched, ZeroMatricesLaunchNothing) {
  // Null planes would fault if an element ran.
  svd3_batched(test::exec(), Mat3Planes<const float>(nullptr, 0), Mat3Planes<float>(nullptr, 0),
               Vec3Planes<float>(nullptr, 0), Mat3Planes<float>(nullptr, 0));
  synchronize(test::exec());
}

TEST(Svd3Batched, MismatchedCountsAreRejected) {
  const Exec& exec = test::exec();
  DeviceBuffer<float> F(exec.backend, 9 * 4), U(exec.backend, 9 * 4), sigma(exec.backend, 3 * 3),
      V(exec.backend, 9 * 4);
  EXPECT_THROW(svd3_batched(exec, Mat3Planes<const float>(F.data(), 4), Mat3Planes<float>(U.data(), 4),
                            Vec3Planes<float>(sigma.data(), 3), Mat3Planes<float>(V.data(), 4)),
               Error);
}

}  // namespace
}  // namespace romp
