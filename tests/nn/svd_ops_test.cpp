// The tensor SVD ops read and write [9, n] plane tensors in place and name the argument a bad call got wrong.
#include <gtest/gtest.h>

#include <string>

#include "kernels/core/error.h"
#include "nn/svd_ops.h"

namespace romp::nn {
namespace {

constexpr int64_t kCount = 257;

// [9, n] planes as [n, 3, 3] matrices, and [3, n] as [n, 3].
torch::Tensor as_matrices(const torch::Tensor& planes) { return planes.t().reshape({-1, 3, 3}); }
torch::Tensor as_vectors(const torch::Tensor& planes) { return planes.t(); }

torch::Tensor random_planes(torch::ScalarType dtype) {
  torch::manual_seed(7);
  return torch::randn({9, kCount}, torch::TensorOptions().dtype(dtype));
}

// The error message of `call`, which must throw romp::Error.
template <class Call>
std::string error_of(const Call& call) {
  try {
    call();
  } catch (const Error& error) {
    return error.what();
  }
  ADD_FAILURE() << "no romp::Error was thrown";
  return "";
}

TEST(SvdOps, DecompositionReconstructsFInEnginePlaneLayout) {
  for (torch::ScalarType dtype : {torch::kFloat32, torch::kFloat64}) {
    const torch::Tensor F = random_planes(dtype);
    const Svd3Tensors svd = svd3(F);
    EXPECT_EQ(svd.U.sizes(), F.sizes());
    EXPECT_EQ(svd.S.sizes(), (std::vector<int64_t>{3, kCount}));
    const torch::Tensor U = as_matrices(svd.U), V = as_matrices(svd.V);
    const torch::Tensor reconstructed = torch::bmm(U * as_vectors(svd.S).unsqueeze(1), V.transpose(1, 2));
    const double tolerance = dtype == torch::kFloat32 ? 1e-5 : 1e-12;
    const torch::Tensor error = (reconstructed - as_matrices(F)).flatten(1).norm(2, 1);
    EXPECT_TRUE(torch::all(error <= tolerance * as_matrices(F).flatten(1).norm(2, 1)).item<bool>());
    EXPECT_TRUE(torch::allclose(torch::det(U), torch::ones({kCount}, F.options()), tolerance, tolerance));
  }
}

TEST(SvdOps, OutVariantWritesIntoTheGivenTensorsAndLeavesFAlone) {
  const torch::Tensor F = random_planes(torch::kFloat32);
  const torch::Tensor F_before = F.clone();
  torch::Tensor U = torch::full({9, kCount}, -7.0f), S = torch::full({3, kCount}, -7.0f),
                V = torch::full({9, kCount}, -7.0f);
  const void* U_memory = U.data_ptr();
  const void* S_memory = S.data_ptr();
  const void* V_memory = V.data_ptr();
  svd3_out(F, U, S, V);
  EXPECT_EQ(U.data_ptr(), U_memory);
  EXPECT_EQ(S.data_ptr(), S_memory);
  EXPECT_EQ(V.data_ptr(), V_memory);
  EXPECT_TRUE(torch::equal(F, F_before));
  const Svd3Tensors fresh = svd3(F);
  EXPECT_TRUE(torch::equal(U, fresh.U));
  EXPECT_TRUE(torch::equal(S, fresh.S));
  EXPECT_TRUE(torch::equal(V, fresh.V));
}

TEST(SvdOps, PolarFactorsReconstructF) {
  const torch::Tensor F = random_planes(torch::kFloat64);
  const Polar3Tensors polar = polar3(F);
  EXPECT_TRUE(torch::allclose(torch::bmm(as_matrices(polar.R), as_matrices(polar.S)), as_matrices(F), 1e-12, 1e-12));
}

TEST(SvdOps, SumOfSingularValuesHasThePolarRotationAsGradient) {
  // d(σ₀ + σ₁ + σ₂)/dF = Σ uₖ vₖᵀ = U Vᵀ = R; undefined dU and dV count as zero.
  const torch::Tensor F = random_planes(torch::kFloat64);
  const Svd3Tensors svd = svd3(F);
  const torch::Tensor dF = svd3_backward(svd.U, svd.S, svd.V, {}, torch::ones_like(svd.S), {});
  EXPECT_TRUE(torch::allclose(dF, polar3(F).R, 1e-12, 1e-12));
}

TEST(SvdOps, PolarBackwardTreatsUndefinedGradientsAsZero) {
  const torch::Tensor F = random_planes(torch::kFloat64);
  const torch::Tensor dR = torch::randn({9, kCount}, F.options());
  EXPECT_TRUE(torch::equal(polar3_backward(F, dR, {}), polar3_backward(F, dR, torch::zeros_like(F))));
  EXPECT_TRUE(torch::equal(polar3_backward(F, {}, {}), torch::zeros_like(F)));
}

TEST(SvdOps, WrongShapeIsNamedWithTheExpectedShape) {
  const std::string message = error_of([] { svd3(torch::zeros({kCount, 9})); });
  EXPECT_NE(message.find("F"), std::string::npos) << message;
  EXPECT_NE(message.find("[9, n]"), std::string::npos) << message;
  EXPECT_NE(message.find("[257, 9]"), std::string::npos) << message;

  const torch::Tensor F = random_planes(torch::kFloat32);
  const std::string out_message = error_of([&] {
    svd3_out(F, torch::empty({9, kCount}), torch::empty({3, kCount - 1}), torch::empty({9, kCount}));
  });
  EXPECT_NE(out_message.find("S: expected shape [3, 257]"), std::string::npos) << out_message;
}

TEST(SvdOps, UnsupportedOrMixedDtypesAreRefused) {
  const std::string message = error_of([] { svd3(torch::zeros({9, 4}, torch::kInt32)); });
  EXPECT_NE(message.find("float32 or float64"), std::string::npos) << message;
  const torch::Tensor F = random_planes(torch::kFloat32);
  EXPECT_THROW(
      svd3_out(F, torch::empty({9, kCount}, torch::kFloat64), torch::empty({3, kCount}), torch::empty({9, kCount})),
      Error);
}

TEST(SvdOps, NonContiguousPlanesAreRefusedNotCopied) {
  const torch::Tensor F = torch::zeros({kCount, 9}).t();  // [9, n] but strided
  EXPECT_THROW(svd3(F), Error);
}

}  // namespace
}  // namespace romp::nn
