// nn::dense: X Wᵀ and its gradients equal LibTorch's matmul in double, float agrees to rounding.
#include "nn/dense_layer.h"

#include <gtest/gtest.h>

#include "kernels/core/error.h"

namespace romp::nn {
namespace {

TEST(DenseLayer, MatchesMatmulAndItsGradients) {
  torch::manual_seed(1);
  const auto f64 = torch::TensorOptions().dtype(torch::kFloat64);
  const torch::Tensor X = torch::randn({257, 13}, f64).requires_grad_(true);
  const torch::Tensor W = torch::randn({64, 13}, f64).requires_grad_(true);
  const torch::Tensor weights = torch::randn({257, 64}, f64);

  const torch::Tensor Y = dense(X, W);
  (Y * weights).sum().backward();
  const torch::Tensor dX = X.grad().clone(), dW = W.grad().clone();
  X.mutable_grad() = torch::Tensor();
  W.mutable_grad() = torch::Tensor();
  const torch::Tensor expected = torch::matmul(X, W.t());
  (expected * weights).sum().backward();

  EXPECT_TRUE(torch::allclose(Y, expected, 1e-13, 1e-13));
  EXPECT_TRUE(torch::allclose(dX, X.grad(), 1e-13, 1e-13));
  EXPECT_TRUE(torch::allclose(dW, W.grad(), 1e-12, 1e-12));
  const torch::Tensor Y_float = dense(X.detach().to(torch::kFloat32), W.detach().to(torch::kFloat32));
  EXPECT_TRUE(torch::allclose(Y_float.to(torch::kFloat64), expected, 1e-5, 1e-5));
}

TEST(DenseLayer, RejectsMismatchedArguments) {
  EXPECT_THROW(dense(torch::zeros({4, 3}), torch::zeros({5, 2})), Error);
  EXPECT_THROW(dense(torch::zeros({4, 3}), torch::zeros({5, 3}, torch::kFloat64)), Error);
  EXPECT_THROW(dense(torch::zeros({4, 3}, torch::kInt32), torch::zeros({5, 3}, torch::kInt32)), Error);
}

}  // namespace
}  // namespace romp::nn
