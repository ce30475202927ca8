// The fused neural law (nn/nclaw/fused_law.h) against the same law composed of LibTorch operators
// (nn/nclaw/composed_law.h): outputs
// and the gradients of F and of every weight, for the elastic and the plastic form, in float64 and float32,
// and on a CUDA device against the CPU where LibTorch has one.
#include <gtest/gtest.h>

#include <cmath>

#include "kernels/core/memory.h"
#include "nn/diffmpm/rollout.h"
#include "nn/nclaw/composed_law.h"
#include "nn/nclaw/fused_law.h"
#include "nn/nclaw/neural_laws.h"

namespace romp::nn::nclaw {
namespace {

torch::TensorOptions options(torch::ScalarType dtype) { return torch::TensorOptions().dtype(dtype); }

// Weights at 3× Xavier scale, so that the GELUs work off their linear part.
LawParameters random_parameters(torch::ScalarType dtype) {
  const auto weight = [&](int64_t outputs, int64_t inputs) {
    return (3.0 * std::sqrt(6.0 / double(outputs + inputs)) *
            (2.0 * torch::rand({outputs, inputs}, options(dtype)) - 1.0))
        .requires_grad_(true);
  };
  return {weight(kLawWidth, kLawInputs), weight(kLawWidth, kLawWidth), weight(kLawOutputs, kLawWidth)};
}

// F near I (the training range), stretched, and inverted ones: [9, n].
torch::Tensor deformations(int64_t n, torch::ScalarType dtype) {
  torch::Tensor F = torch::eye(3, options(dtype)).reshape({9, 1}) + 0.4 * torch::randn({9, n}, options(dtype));
  F.narrow(1, 0, n / 4)
      .mul_(torch::tensor({1.0, 1.0, 1.0, 1.0, 1.0, 1.0, -1.0, -1.0, -1.0}, options(dtype)).reshape({9, 1}));
  return F;
}

double relative_difference(const torch::Tensor& result, const torch::Tensor& expected) {
  return (result - expected).abs().max().item<double>() / expected.abs().max().item<double>();
}

struct Evaluation {
  torch::Tensor Y, dF, d_input, d_hidden, d_output;
};

template <class Law>
Evaluation evaluate(const Law& law, const torch::Tensor& F0, const LawParameters& w, const torch::Tensor& upstream) {
  for (const torch::Tensor& weight : {w.input, w.hidden, w.output})
    if (weight.grad().defined()) weight.grad().zero_();
  const torch::Tensor F = F0.detach().clone().requires_grad_(true);
  const torch::Tensor Y = law(F, w);
  (Y * upstream).sum().backward();
  return {Y.detach(), F.grad(), w.input.grad().clone(), w.hidden.grad().clone(), w.output.grad().clone()};
}

void expect_same_law(torch::ScalarType dtype, double tolerance) {
  torch::manual_seed(11);
  const int64_t n = 300;
  const LawParameters w = random_parameters(dtype);
  const torch::Tensor F = deformations(n, dtype), upstream = torch::randn({9, n}, options(dtype));
  for (const auto& [scale, adds_input] : {std::pair{1.0, false}, std::pair{kPlasticStep, true}}) {
    SCOPED_TRACE(adds_input ? "plastic form" : "elastic form");
    const auto fused = [&](const torch::Tensor& f, const LawParameters& p) {
      return fused_law(f, p, scale, adds_input);
    };
    const auto reference = [&](const torch::Tensor& f, const LawParameters& p) {
      return composed_law(f, p, scale, adds_input);
    };
    const Evaluation result = evaluate(fused, F, w, upstream), expected = evaluate(reference, F, w, upstream);
    EXPECT_LE(relative_difference(result.Y - (adds_input ? F : torch::zeros_like(F)),
                                  expected.Y - (adds_input ? F : torch::zeros_like(F))),
              tolerance);
    EXPECT_LE(relative_difference(result.dF, expected.dF), tolerance);
    EXPECT_LE(relative_difference(result.d_input, expected.d_input), tolerance);
    EXPECT_LE(relative_difference(result.d_hidden, expected.d_hidden), tolerance);
    EXPECT_LE(relative_difference(result.d_output, expected.d_output), tolerance);
  }
}

TEST(FusedLaw, MatchesTheOperatorByOperatorLawInDouble) { expect_same_law(torch::kFloat64, 1e-11); }

TEST(FusedLaw, MatchesTheOperatorByOperatorLawInFloat) { expect_same_law(torch::kFloat32, 2e-4); }

// The weight gradients against central differences of the loss (float64), a few entries of each matrix.
TEST(FusedLaw, WeightGradientsMatchCentralDifferences) {
  torch::manual_seed(12);
  const int64_t n = 40;
  const LawParameters w = random_parameters(torch::kFloat64);
  const torch::Tensor F = deformations(n, torch::kFloat64), upstream = torch::randn({9, n}, options(torch::kFloat64));
  const auto loss = [&] { return (fused_law(F, w, 1.0, false) * upstream).sum(); };
  loss().backward();
  torch::NoGradGuard no_grad;
  for (const torch::Tensor& weight : {w.input, w.hidden, w.output}) {
    double* values = weight.data_ptr<double>();
    const double* gradient = weight.grad().data_ptr<double>();
    for (int64_t i = 0; i < weight.numel(); i += 37) {
      const double original = values[i], h = 1e-6;
      values[i] = original + h;
      const double plus = loss().item<double>();
      values[i] = original - h;
      const double minus = loss().item<double>();
      values[i] = original;
      const double difference = (plus - minus) / (2.0 * h);
      EXPECT_NEAR(gradient[i], difference, 1e-6 * std::max(1.0, std::abs(difference))) << "entry " << i;
    }
  }
}

TEST(FusedLaw, RefusesWrongShapesNamingTheTensor) {
  const LawParameters w = random_parameters(torch::kFloat32);
  try {
    fused_law(torch::zeros({3, 5}), w, 1.0, false);
    FAIL() << "a [3, 5] F was accepted";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find("F must be [9, n]"), std::string::npos) << error.what();
  }
  LawParameters narrow = w;
  narrow.hidden = torch::zeros({32, 64});
  try {
    fused_law(torch::zeros({9, 5}), narrow, 1.0, false);
    FAIL() << "a [32, 64] hidden weight was accepted";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find("hidden weight must be [64, 64]"), std::string::npos) << error.what();
  }
}

// A teacher-forcing segment (substeps with both laws, forward and backward) asks the host for nothing: no
// romp allocation, upload or download, so on CUDA nothing in it waits for the device (the loss's item() at
// the segment's end is the one wait) and the segment can be captured as a graph.
TEST(FusedLaw, ATrainingSegmentMakesNoHostRoundTrip) {
  torch::manual_seed(14);
  const int64_t n = 64;
  const diffmpm::DiffMpm sim(diffmpm::DiffMpmConfig{}, torch::full({n}, 1e-3), torch::full({n}, 1e-6));
  const diffmpm::MpmState initial{0.4 + 0.2 * torch::rand({3, n}), torch::zeros({3, n}), torch::zeros({9, n}),
                                  torch::eye(3).reshape({9, 1}).expand({9, n}).contiguous()};
  const NeuralLaws laws = seeded_laws(15, torch::TensorOptions().dtype(torch::kFloat32));
  const diffmpm::Rollout warm_up =
      diffmpm::rollout(sim, initial, laws.constitutive(), {2, 0});  // first-use allocations
  warm_up.positions.sum().backward();
  const memory::Traffic before = memory::traffic();
  const diffmpm::Rollout segment = diffmpm::rollout(sim, initial, laws.constitutive(), {10, 0});
  segment.positions.square().sum().backward();
  const memory::Traffic after = memory::traffic();
  EXPECT_EQ(after.allocations, before.allocations);
  EXPECT_EQ(after.uploads, before.uploads);
  EXPECT_EQ(after.downloads, before.downloads);
}

// The CUDA kernels against the CPU ones, forward and backward, in float32 (the training dtype).
TEST(FusedLaw, CudaMatchesCpu) {
  if (!torch::cuda::is_available()) GTEST_SKIP() << "LibTorch has no CUDA device here";
  torch::manual_seed(13);
  const int64_t n = 2000;
  const LawParameters w = random_parameters(torch::kFloat32);
  const auto on_cuda = [](const torch::Tensor& t) { return t.detach().to(torch::kCUDA).requires_grad_(true); };
  const LawParameters w_cuda{on_cuda(w.input), on_cuda(w.hidden), on_cuda(w.output)};
  const torch::Tensor F = deformations(n, torch::kFloat32), upstream = torch::randn({9, n});
  const auto fused = [](const torch::Tensor& f, const LawParameters& p) { return fused_law(f, p, 1.0, false); };
  const Evaluation cpu = evaluate(fused, F, w, upstream);
  const Evaluation cuda = evaluate(fused, F.to(torch::kCUDA), w_cuda, upstream.to(torch::kCUDA));
  EXPECT_LE(relative_difference(cuda.Y.cpu(), cpu.Y), 1e-5);
  EXPECT_LE(relative_difference(cuda.dF.cpu(), cpu.dF), 1e-4);
  EXPECT_LE(relative_difference(cuda.d_hidden.cpu(), cpu.d_hidden), 1e-4);
}

}  // namespace
}  // namespace romp::nn::nclaw
