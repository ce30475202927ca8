// ∇_X g and ∂g/∂x̂ of the deformation map, by forward-mode tangents and by autograd, against central finite
// differences in double; the loss's parameter gradients agree between the two; the encoder's layer rule.
#include "nn/rom/manifold_derivatives.h"

#include <gtest/gtest.h>

#include "nn/rom/deformation_map.h"
#include "nn/rom/encoder.h"
#include "nn/rom/rom_loss.h"

namespace romp::nn::rom {
namespace {

constexpr std::int64_t kLatent = 3;
constexpr std::int64_t kPoints = 16;

torch::Tensor values(std::initializer_list<double> v) { return torch::tensor(std::vector<double>(v), torch::kFloat64); }

// A map in double with a normalisation that is not the identity, so its chain rule is exercised too.
DeformationMap double_map(std::int64_t hidden_layers) {
  torch::manual_seed(7);
  MapNormalisation n{values({-1.0, 0.0, 0.5}), values({1.0, 2.0, 0.8}), values({0.1, -0.2, 0.05}),
                     values({0.3, 0.2, 0.4})};
  DeformationMap g(MapArchitecture{kLatent, hidden_layers, 30}, n);
  g->to(torch::kFloat64);
  return g;
}

struct Inputs {
  torch::Tensor xhat, X;
};

Inputs random_inputs() {
  torch::manual_seed(11);
  const auto options = torch::TensorOptions(torch::kFloat64);
  return {torch::randn({kPoints, kLatent}, options),
          torch::rand({kPoints, 3}, options) * values({2.0, 2.0, 0.3}) + values({-1.0, 0.0, 0.5})};
}

// Central differences of g along coordinate `k` of `input` (X or x̂): [N, 3].
torch::Tensor finite_difference(const DeformationMapImpl& g, const Inputs& in, bool of_X, std::int64_t k) {
  constexpr double h = 1e-6;
  Inputs plus = {in.xhat.clone(), in.X.clone()}, minus = {in.xhat.clone(), in.X.clone()};
  (of_X ? plus.X : plus.xhat).select(1, k).add_(h);
  (of_X ? minus.X : minus.xhat).select(1, k).sub_(h);
  torch::NoGradGuard no_grad;
  return (g.forward(plus.xhat, plus.X) - g.forward(minus.xhat, minus.X)) / (2 * h);
}

class ManifoldDerivatives : public ::testing::TestWithParam<std::tuple<DerivativeMethod, std::int64_t>> {};

TEST_P(ManifoldDerivatives, MatchCentralFiniteDifferences) {
  const auto [method, hidden_layers] = GetParam();
  const DeformationMap g = double_map(hidden_layers);
  const Inputs in = random_inputs();
  const ManifoldJacobians j = manifold_jacobians(*g, in.xhat, in.X, method, /*create_graph=*/false);
  ASSERT_EQ(j.F.sizes(), (std::vector<std::int64_t>{kPoints, 3, 3}));
  ASSERT_EQ(j.dx.sizes(), (std::vector<std::int64_t>{kPoints, 3, kLatent}));
  EXPECT_TRUE(torch::allclose(j.x, g->forward(in.xhat, in.X), 0.0, 1e-14));
  for (std::int64_t k = 0; k < 3; ++k) {
    EXPECT_TRUE(torch::allclose(j.F.select(2, k), finite_difference(*g, in, true, k), 1e-7, 1e-8)) << "∂x/∂X_" << k;
  }
  for (std::int64_t k = 0; k < kLatent; ++k) {
    EXPECT_TRUE(torch::allclose(j.dx.select(2, k), finite_difference(*g, in, false, k), 1e-7, 1e-8)) << "∂x/∂x̂_" << k;
  }
}

TEST_P(ManifoldDerivatives, DirectionalTangentIsTheJacobianTimesTheDirection) {
  const auto [method, hidden_layers] = GetParam();
  const DeformationMap g = double_map(hidden_layers);
  const Inputs in = random_inputs();
  const torch::Tensor directions = torch::randn({kPoints, kLatent, 2}, torch::kFloat64);
  const ManifoldJacobians full = manifold_jacobians(*g, in.xhat, in.X, method, false);
  const ManifoldJacobians along = manifold_jacobians(*g, in.xhat, in.X, directions, method, false);
  EXPECT_TRUE(torch::allclose(along.dx, full.dx.matmul(directions), 1e-12, 1e-12));
  EXPECT_TRUE(torch::allclose(along.F, full.F, 1e-12, 1e-12));
}

INSTANTIATE_TEST_SUITE_P(MethodsAndDepths, ManifoldDerivatives,
                         ::testing::Combine(::testing::Values(DerivativeMethod::Analytic, DerivativeMethod::Autograd),
                                            ::testing::Values(std::int64_t(5), std::int64_t(0))),
                         [](const auto& info) {
  return std::string(to_string(std::get<0>(info.param))) + (std::get<1>(info.param) == 0 ? "Linear" : "Mlp");
});

TEST(ManifoldDerivatives, LossGradientsAgreeBetweenMethods) {
  const DeformationMap g = double_map(5);
  const Inputs in = random_inputs();
  const auto options = torch::TensorOptions(torch::kFloat64);
  const torch::Tensor xhat = in.xhat.clone().requires_grad_(true);
  LossBatch batch{xhat,
                  torch::randn({kPoints, kLatent}, options),
                  in.X,
                  torch::randn({kPoints, 3}, options),
                  torch::randn({kPoints, 3}, options),
                  torch::randn({kPoints, 3, 3}, options),
                  (torch::arange(kPoints) % 3 != 0).to(torch::kFloat64)};
  std::vector<std::vector<torch::Tensor>> gradients;
  for (DerivativeMethod method : {DerivativeMethod::Analytic, DerivativeMethod::Autograd}) {
    const LossTerms terms = rom_loss(*g, batch, LossWeights{}, method);
    std::vector<torch::Tensor> wrt = g->parameters();
    wrt.push_back(xhat);
    gradients.push_back(torch::autograd::grad({terms.total}, wrt));
  }
  ASSERT_EQ(gradients[0].size(), gradients[1].size());
  for (std::size_t i = 0; i < gradients[0].size(); ++i)
    EXPECT_TRUE(torch::allclose(gradients[0][i], gradients[1][i], 1e-10, 1e-12)) << "tensor " << i;
}

TEST(Encoder, ConvolvesUntilTheFlattenedLengthIsAsLowAsPossibleButAtLeast32) {
  EXPECT_EQ(encoder_conv_layers(500), 5);  // 500 → 248 → 122 → 59 → 27 → 11 (33 values; 3 would be 9)
  EXPECT_EQ(encoder_conv_layers(12), 0);   // 36 values already; one more would leave 12
  const torch::Tensor box_min = torch::zeros({3}), box_max = torch::ones({3});
  const Encoder e(500, 4, box_min, box_max);
  EXPECT_EQ(e->conv_features(), 33);
  EXPECT_EQ(e->forward(torch::rand({2, 500, 3})).sizes(), (std::vector<std::int64_t>{2, 4}));
}

}  // namespace
}  // namespace romp::nn::rom
