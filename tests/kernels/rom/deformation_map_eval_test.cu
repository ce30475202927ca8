// The fused deformation-map evaluator against an independent Eigen reference: values exactly (to
// rounding), ∇_X g and ∂g/∂x̂ against central finite differences of the reference in double, float
// against double, the linear baseline's closed form, and its size checks. Runs on the test backend.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/error.h"
#include "kernels/rom/deformation_map_eval.h"
#include "tests/kernels/rom/reference_map.h"
#include "tests/support/test_exec.h"

namespace romp::rom {
namespace {

// The evaluator's outputs for `points` (reference positions) at `xhat`, on the test backend.
template <class T>
struct Evaluation {
  std::vector<T> x, F, dg_dxhat;  // planes, as the kernel writes them
  Index n = 0;
};

template <class T>
Evaluation<T> evaluate(const ReferenceMap& reference, int hidden_layers, int width, const Eigen::VectorXd& xhat,
                       const std::vector<Eigen::Vector3d>& points, MapKernel kernel = MapKernel::Fastest) {
  const Exec& exec = test::exec();
  const Index n = Index(points.size());
  const int r = reference.latent;
  std::vector<T> xhat_host(xhat.data(), xhat.data() + r), X_host(3 * n);
  for (Index i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) X_host[c * n + i] = T(points[i](c));

  const UploadedMap<T> uploaded = upload<T>(exec, reference, hidden_layers, width);
  const DeformationMapView<T>& map = uploaded.view;
  const auto xhat_buffer = DeviceBuffer<T>::from_host(exec.backend, xhat_host, exec.stream);
  const auto X = DeviceBuffer<T>::from_host(exec.backend, X_host, exec.stream);
  DeviceBuffer<T> x(exec.backend, 3 * n), F(exec.backend, 9 * n), dg(exec.backend, 3 * r * n);

  evaluate_deformation_map<T>(exec, map, Span<const T>(xhat_buffer.data(), r), Vec3Planes<const T>(X.data(), n),
                              {Vec3Planes<T>(x.data(), n), Mat3Planes<T>(F.data(), n), Span<T>(dg.data(), dg.size())},
                              kernel);
  return {x.to_host(exec.stream), F.to_host(exec.stream), dg.to_host(exec.stream), n};
}

std::vector<Eigen::Vector3d> sample_points(int count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i)
    points.emplace_back(-0.1 + 0.3 * unit(random), 0.2 + 0.4 * unit(random), 0.05 + 0.2 * unit(random));
  return points;
}

// Central differences of the reference: column c of ∇_X g and column j of ∂g/∂x̂ at one point.
constexpr double kStep = 1e-6;

Eigen::Matrix3d reference_F(const ReferenceMap& map, const Eigen::VectorXd& xhat, const Eigen::Vector3d& X) {
  Eigen::Matrix3d F;
  for (int c = 0; c < 3; ++c) {
    const Eigen::Vector3d h = Eigen::Vector3d::Unit(c) * kStep;
    F.col(c) = (map.g(xhat, X + h) - map.g(xhat, X - h)) / (2.0 * kStep);
  }
  return F;
}

Eigen::MatrixXd reference_dg_dxhat(const ReferenceMap& map, const Eigen::VectorXd& xhat, const Eigen::Vector3d& X) {
  Eigen::MatrixXd J(3, map.latent);
  for (int j = 0; j < map.latent; ++j) {
    const Eigen::VectorXd h = Eigen::VectorXd::Unit(map.latent, j) * kStep;
    J.col(j) = (map.g(xhat + h, X) - map.g(xhat - h, X)) / (2.0 * kStep);
  }
  return J;
}

// Largest deviation of the evaluation from the reference over every point, relative to each
// quantity's largest entry: values, ∇_X g, ∂g/∂x̂.
template <class T>
Eigen::Vector3d deviations(const ReferenceMap& map, const Evaluation<T>& e, const Eigen::VectorXd& xhat,
                           const std::vector<Eigen::Vector3d>& points) {
  const Index n = e.n;
  const int r = map.latent;
  Eigen::Vector3d largest_error = Eigen::Vector3d::Zero(), largest_value = Eigen::Vector3d::Zero();
  for (Index i = 0; i < n; ++i) {
    const Eigen::Vector3d g = map.g(xhat, points[i]);
    const Eigen::Matrix3d F = reference_F(map, xhat, points[i]);
    const Eigen::MatrixXd J = reference_dg_dxhat(map, xhat, points[i]);
    for (int o = 0; o < 3; ++o) {
      largest_error(0) = std::max(largest_error(0), std::abs(double(e.x[o * n + i]) - g(o)));
      largest_value(0) = std::max(largest_value(0), std::abs(g(o)));
      for (int c = 0; c < 3; ++c) {
        largest_error(1) = std::max(largest_error(1), std::abs(double(e.F[(3 * o + c) * n + i]) - F(o, c)));
        largest_value(1) = std::max(largest_value(1), std::abs(F(o, c)));
      }
      for (int j = 0; j < r; ++j) {
        largest_error(2) = std::max(largest_error(2), std::abs(double(e.dg_dxhat[(o * r + j) * n + i]) - J(o, j)));
        largest_value(2) = std::max(largest_value(2), std::abs(J(o, j)));
      }
    }
  }
  return largest_error.cwiseQuotient(largest_value);
}

TEST(DeformationMapEval, PaperSizedMapMatchesTheReferenceAndItsFiniteDifferencesInDouble) {
  const int r = 6, hidden = 5, width = 30;
  const ReferenceMap map = random_map(r, hidden, width, 1);
  const Eigen::VectorXd xhat = Eigen::VectorXd::LinSpaced(r, -0.8, 0.7);
  const std::vector<Eigen::Vector3d> points = sample_points(300, 2);
  const Eigen::Vector3d error = deviations(map, evaluate<double>(map, hidden, width, xhat, points), xhat, points);
  EXPECT_LT(error(0), 1e-14);  // the same arithmetic in another order
  EXPECT_LT(error(1), 1e-8);   // central differences: truncation ~h², rounding ~ε/h
  EXPECT_LT(error(2), 1e-8);
}

TEST(DeformationMapEval, FloatAgreesWithTheDoubleReferenceToFloatRounding) {
  const int r = 8, hidden = 5, width = 30;
  const ReferenceMap map = random_map(r, hidden, width, 3);
  const Eigen::VectorXd xhat = Eigen::VectorXd::LinSpaced(r, 0.5, -0.5);
  const std::vector<Eigen::Vector3d> points = sample_points(300, 4);
  const Eigen::Vector3d error = deviations(map, evaluate<float>(map, hidden, width, xhat, points), xhat, points);
  EXPECT_LT(error(0), 1e-6);
  EXPECT_LT(error(1), 1e-5);
  EXPECT_LT(error(2), 1e-5);
}

// The fixed-shape kernels (the papers' 5 × 30 network at r = 4, 6, 7) against the generic one on the
// same inputs: the same arithmetic in another order, so equal to float rounding, and as close to the
// reference as the generic float kernel is.
TEST(DeformationMapEval, FixedShapeKernelsMatchTheGenericOne) {
  for (const int r : {4, 6, 7}) {
    const int hidden = 5, width = 30;
    const ReferenceMap map = random_map(r, hidden, width, 20 + r);
    const Eigen::VectorXd xhat = Eigen::VectorXd::LinSpaced(r, -0.8, 0.7);
    const std::vector<Eigen::Vector3d> points = sample_points(96, 4);
    const Evaluation<float> fixed = evaluate<float>(map, hidden, width, xhat, points, MapKernel::Fixed);
    const Evaluation<float> generic = evaluate<float>(map, hidden, width, xhat, points, MapKernel::Generic);
    const auto largest = [](const std::vector<float>& a, const std::vector<float>& b) {
      float difference = 0.0f, size = 0.0f;
      for (std::size_t k = 0; k < a.size(); ++k) {
        difference = std::max(difference, std::abs(a[k] - b[k]));
        size = std::max(size, std::abs(b[k]));
      }
      return difference / size;
    };
    EXPECT_LT(largest(fixed.x, generic.x), 1e-6f) << "r = " << r;
    EXPECT_LT(largest(fixed.F, generic.F), 1e-5f) << "r = " << r;
    EXPECT_LT(largest(fixed.dg_dxhat, generic.dg_dxhat), 1e-5f) << "r = " << r;
    const Eigen::Vector3d error = deviations(map, fixed, xhat, points);
    EXPECT_LT(error(0), 1e-6) << "r = " << r;
    EXPECT_LT(error(1), 1e-5) << "r = " << r;
    EXPECT_LT(error(2), 1e-5) << "r = " << r;
  }
}

TEST(DeformationMapEval, AFixedShapeKernelForSizesThatHaveNoneIsAnError) {
  const ReferenceMap map = random_map(5, 5, 30, 3);  // r = 5: no fixed-shape kernel
  const std::vector<Eigen::Vector3d> points = sample_points(8, 2);
  const Eigen::VectorXd xhat = Eigen::VectorXd::Zero(5);
  EXPECT_THROW(evaluate<float>(map, 5, 30, xhat, points, MapKernel::Fixed), Error);
  EXPECT_NO_THROW(evaluate<float>(map, 5, 30, xhat, points, MapKernel::Fastest));
  const ReferenceMap paper = random_map(6, 5, 30, 3);
  EXPECT_THROW(evaluate<double>(paper, 5, 30, Eigen::VectorXd::Zero(6), points, MapKernel::Fixed), Error);
}

TEST(DeformationMapEval, LinearBaselineHasItsClosedFormJacobian) {
  // H = 0: out = W [x̂, X̄] + b, so ∇_X g = I + diag(u_std) W[:, r:] diag(X_scale), the same at every point.
  const int r = 4;
  const ReferenceMap map = random_map(r, 0, 0, 5);
  const Eigen::VectorXd xhat = Eigen::VectorXd::LinSpaced(r, 1.0, 2.0);
  const std::vector<Eigen::Vector3d> points = sample_points(50, 6);
  const Evaluation<double> e = evaluate<double>(map, 0, 0, xhat, points);
  const Eigen::Matrix3d F =
      Eigen::Matrix3d::Identity() + map.u_std.asDiagonal() * map.weights[0].rightCols(3) * map.X_scale.asDiagonal();
  const Eigen::MatrixXd J = map.u_std.asDiagonal() * map.weights[0].leftCols(r);
  for (Index i = 0; i < e.n; ++i)
    for (int o = 0; o < 3; ++o) {
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(e.F[(3 * o + c) * e.n + i], F(o, c), 1e-15);
      for (int j = 0; j < r; ++j) EXPECT_NEAR(e.dg_dxhat[(o * r + j) * e.n + i], J(o, j), 1e-15);
    }
}

TEST(DeformationMapEval, OutputsLeftEmptyAreSkippedAndTheOthersUnchanged) {
  const Exec& exec = test::exec();
  const int r = 3, hidden = 2, width = 8;
  const ReferenceMap reference = random_map(r, hidden, width, 7);
  const std::vector<Eigen::Vector3d> points = sample_points(20, 8);
  const Eigen::VectorXd xhat = Eigen::VectorXd::Constant(r, 0.25);
  const Evaluation<double> all = evaluate<double>(reference, hidden, width, xhat, points);

  const Index n = Index(points.size());
  const auto parameters = DeviceBuffer<double>::from_host(exec.backend, reference.packed(), exec.stream);
  const auto xhat_buffer =
      DeviceBuffer<double>::from_host(exec.backend, std::vector<double>(xhat.data(), xhat.data() + r), exec.stream);
  std::vector<double> X_host(3 * n);
  for (Index i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) X_host[c * n + i] = points[i](c);
  const auto X_points = DeviceBuffer<double>::from_host(exec.backend, X_host, exec.stream);
  DeviceBuffer<double> F(exec.backend, 9 * n);
  DeformationMapView<double> map{r,
                                 hidden,
                                 width,
                                 Span<const double>(parameters.data(), parameters.size()),
                                 nullptr,
                                 vec3<double>(reference.X_min),
                                 vec3<double>(reference.X_scale),
                                 vec3<double>(reference.u_mean),
                                 vec3<double>(reference.u_std)};
  DeformationMapOutputs<double> only_F;
  only_F.F = Mat3Planes<double>(F.data(), n);
  evaluate_deformation_map<double>(exec, map, Span<const double>(xhat_buffer.data(), r),
                                   Vec3Planes<const double>(X_points.data(), n), only_F);
  EXPECT_EQ(F.to_host(exec.stream), all.F);
}

TEST(DeformationMapEval, SizesBeyondTheKernelsLimitsAreErrors) {
  const Exec& exec = test::exec();
  DeviceBuffer<float> X(exec.backend, 3), xhat(exec.backend, kMaxMapLatent + 1);
  const int too_wide = kMaxMapWidth + 1;
  DeviceBuffer<float> parameters(exec.backend, deformation_map_parameter_count(2, 1, too_wide));
  DeformationMapView<float> map;
  map.latent = 2;
  map.hidden_layers = 1;
  map.width = too_wide;
  map.parameters = Span<const float>(parameters.data(), parameters.size());
  DeformationMapOutputs<float> out;
  const Vec3Planes<const float> points(X.data(), 1);
  EXPECT_THROW(evaluate_deformation_map<float>(exec, map, Span<const float>(xhat.data(), 2), points, out), Error);
  map.width = 8;  // the buffer now holds more values than the sizes need
  EXPECT_THROW(evaluate_deformation_map<float>(exec, map, Span<const float>(xhat.data(), 2), points, out), Error);
  map.latent = kMaxMapLatent + 1;
  EXPECT_THROW(evaluate_deformation_map<float>(exec, map, Span<const float>(xhat.data(), map.latent), points, out),
               Error);
}

}  // namespace
}  // namespace romp::rom
