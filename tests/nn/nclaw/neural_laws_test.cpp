// The neural laws of Ma et al. 2023 (Alg. 4): exact rest state, rotation equivariance, finite outputs
// and gradients for extreme F, and F-gradients against central differences.
#include <gtest/gtest.h>

#include <cmath>

#include "nn/nclaw/features.h"
#include "nn/nclaw/neural_laws.h"
#include "tests/nn/diffmpm/gradient_check.h"

namespace romp::nn::nclaw {
namespace {

constexpr int64_t kCount = 512;

torch::TensorOptions options(torch::ScalarType dtype) { return torch::TensorOptions().dtype(dtype); }

// n random proper rotations [n, 3, 3]: exponentials of random skew matrices.
torch::Tensor random_rotations(int64_t n, torch::ScalarType dtype) {
  const torch::Tensor K = 2.0 * torch::randn({n, 3, 3}, options(dtype));
  return torch::matrix_exp(K - K.transpose(1, 2));
}

// F = U diag(σ) Vᵀ [9, n] with σ log-uniform in [low, high]; det F < 0 for every other matrix.
torch::Tensor deformations(int64_t n, double low, double high, torch::ScalarType dtype) {
  torch::Tensor sigma =
      torch::exp(std::log(low) + (std::log(high) - std::log(low)) * torch::rand({n, 3}, options(dtype)));
  torch::Tensor flip = torch::ones({n, 3}, options(dtype));
  flip.index_put_({torch::indexing::Slice(0, torch::indexing::None, 2), 2}, -1.0);
  sigma = sigma * flip;
  const torch::Tensor U = random_rotations(n, dtype), V = random_rotations(n, dtype);
  return matrices_to_planes(torch::bmm(U * sigma.unsqueeze(1), V.transpose(1, 2)));
}

torch::Tensor identities(int64_t n, torch::ScalarType dtype) {
  return matrices_to_planes(torch::eye(3, options(dtype)).expand({n, 3, 3}));
}

double max_abs(const torch::Tensor& tensor) { return tensor.abs().max().item<double>(); }

TEST(NeuralLaws, HaveTheAuthorsParameterCount) {
  // App. D.2: "a total of 11,008 parameters" for the two laws.
  int64_t total = 0;
  for (const torch::Tensor& p : ElasticLaw()->parameters()) total += p.numel();
  for (const torch::Tensor& p : PlasticLaw()->parameters()) total += p.numel();
  EXPECT_EQ(total, 11008);
}

TEST(NeuralLaws, StressIsZeroAndFUnchangedAtIdentityExactly) {
  for (torch::ScalarType dtype : {torch::kFloat32, torch::kFloat64}) {
    const NeuralLaws laws = seeded_laws(1, options(dtype));
    ElasticLaw elastic = laws.elastic;
    PlasticLaw plastic = laws.plastic;
    const torch::Tensor F = identities(kCount, dtype);
    EXPECT_TRUE(torch::equal(invariant_features(planes_to_matrices(F), stretch_and_rotation(F).sigma),
                             torch::zeros({kCount, kLawInputs}, options(dtype))));
    EXPECT_TRUE(torch::equal(elastic->forward(F), torch::zeros_like(F)));
    EXPECT_TRUE(torch::equal(plastic->forward(F), F));
  }
}

// P(Q F) = Q P(F) and F_new(Q F) = Q F_new(F) (App. C.3) for random F and rotations Q.
TEST(NeuralLaws, RotatingFRotatesTheirOutputs) {
  const torch::ScalarType dtype = torch::kFloat64;
  const NeuralLaws laws = seeded_laws(2, options(dtype));
  ElasticLaw elastic = laws.elastic;
  PlasticLaw plastic = laws.plastic;
  const torch::Tensor F = deformations(kCount, 0.3, 3.0, dtype);
  const torch::Tensor Q = random_rotations(kCount, dtype);
  const torch::Tensor rotated = matrices_to_planes(torch::bmm(Q, planes_to_matrices(F)));
  for (const auto& law :
       {std::function<torch::Tensor(const torch::Tensor&)>([&](const torch::Tensor& f) { return elastic->forward(f); }),
        std::function<torch::Tensor(const torch::Tensor&)>(
            [&](const torch::Tensor& f) { return plastic->forward(f); })}) {
    const torch::Tensor expected = torch::bmm(Q, planes_to_matrices(law(F)));
    const torch::Tensor result = planes_to_matrices(law(rotated));
    EXPECT_LE(max_abs(result - expected), 1e-6 * max_abs(expected));
  }
}

// σ from 1e-3 to 1e3 with det F < 0 for half of them: outputs and their F-gradients stay finite.
TEST(NeuralLaws, StayFiniteForExtremeDeformations) {
  for (torch::ScalarType dtype : {torch::kFloat32, torch::kFloat64}) {
    const NeuralLaws laws = seeded_laws(3, options(dtype));
    ElasticLaw elastic = laws.elastic;
    PlasticLaw plastic = laws.plastic;
    const torch::Tensor F = deformations(kCount, 1e-3, 1e3, dtype).requires_grad_(true);
    const torch::Tensor P = elastic->forward(F), F_new = plastic->forward(F);
    EXPECT_TRUE(torch::isfinite(P).all().item<bool>());
    EXPECT_TRUE(torch::isfinite(F_new).all().item<bool>());
    (P.sum() + F_new.sum()).backward();
    EXPECT_TRUE(torch::isfinite(F.grad()).all().item<bool>());
  }
}

// Gradients at F = I (three equal singular values) are finite: the rotation's backward pass has
// only σᵢ + σⱼ gaps.
TEST(NeuralLaws, GradientIsFiniteAtIdentity) {
  torch::manual_seed(4);
  ElasticLaw elastic;
  const torch::Tensor F = identities(kCount, torch::kFloat32).requires_grad_(true);
  (elastic->forward(F) * torch::randn({9, kCount})).sum().backward();
  EXPECT_TRUE(torch::isfinite(F.grad()).all().item<bool>());
}

TEST(NeuralLaws, ElasticGradientMatchesCentralDifferences) {
  torch::manual_seed(5);
  const torch::ScalarType dtype = torch::kFloat64;
  ElasticLaw elastic;
  elastic->to(dtype);
  const int64_t n = 32;
  const torch::Tensor F = deformations(n, 0.5, 2.0, dtype).requires_grad_(true);
  const torch::Tensor weights = torch::randn({9, n}, options(dtype));
  const auto loss = [&] { return (elastic->forward(F) * weights).sum(); };
  loss().backward();
  const double error = test::finite_difference_error(F, F.grad(), [&] { return loss().item<double>(); });
  EXPECT_LE(error, 1e-5);
}

}  // namespace
}  // namespace romp::nn::nclaw
