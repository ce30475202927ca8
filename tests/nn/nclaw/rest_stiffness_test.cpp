// Rest stiffness: recovers the Lamé parameters of a known law, and of a learned law finds what it
// was made to be.
#include <gtest/gtest.h>

#include "kernels/material/lame.h"
#include "nn/nclaw/fixed_corotated.h"
#include "nn/nclaw/neural_laws.h"
#include "nn/nclaw/rest_stiffness.h"

namespace romp::nn::nclaw {
namespace {

TEST(RestStiffness, RecoversTheLameParametersOfFixedCorotated) {
  const auto options = torch::TensorOptions().dtype(torch::kFloat64);
  const torch::Tensor youngs = torch::tensor(2.0e5, options), poisson = torch::tensor(0.3, options);
  const RestStiffness found =
      rest_stiffness([&](const torch::Tensor& F) { return fixed_corotated_stress(F, youngs, poisson); });
  const material::Lame<double> expected = material::lame_from_young_poisson(2.0e5, 0.3);
  EXPECT_NEAR(found.mu, expected.mu, 1e-6 * expected.mu);
  EXPECT_NEAR(found.lambda, expected.lambda, 1e-6 * expected.lambda);
}

TEST(RestStiffness, OfALinearLawIsItsCoefficients) {
  // P = 3 (H + Hᵀ) + 5 tr(H) I with H = F − I: μ = 3, λ = 5 exactly.
  const auto linear = [](const torch::Tensor& F) {
    const torch::Tensor H = F - torch::eye(3, F.options()).reshape({9, 1});
    const torch::Tensor trace = H[0] + H[4] + H[8];
    torch::Tensor P = 3.0 * (H + H.reshape({3, 3, -1}).transpose(0, 1).reshape({9, -1}));
    for (int64_t d : {0, 4, 8}) P[d] += 5.0 * trace;
    return P;
  };
  const RestStiffness found = rest_stiffness(linear);
  EXPECT_NEAR(found.mu, 3.0, 1e-9);
  EXPECT_NEAR(found.lambda, 5.0, 1e-9);
  EXPECT_NEAR(found.p_wave_modulus(), 11.0, 1e-9);
}

TEST(RestStiffness, OfAnUntrainedLawIsFiniteAndRunsOnItsDtype) {
  NeuralLaws laws = seeded_laws(3, torch::kFloat64);
  const RestStiffness found = rest_stiffness([&](const torch::Tensor& F) { return laws.elastic->forward(F); });
  EXPECT_TRUE(std::isfinite(found.mu) && std::isfinite(found.lambda));
}

}  // namespace
}  // namespace romp::nn::nclaw
