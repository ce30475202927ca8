// Differentiable MPM through LibTorch: gradients of rollouts with respect to the initial state, the
// stress, material parameters and network weights against central differences in double;
// checkpointed rollouts against the full graph; the float training scene end to end.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "kernels/core/error.h"
#include "nn/diffmpm/mpm_step.h"
#include "nn/diffmpm/rollout.h"
#include "nn/nclaw/fixed_corotated.h"
#include "nn/nclaw/neural_laws.h"
#include "tests/nn/diffmpm/gradient_check.h"

namespace romp::nn::diffmpm {
namespace {

// The bound for gradients in double.
constexpr double kGradientTolerance = 1e-5;

struct Scene {
  DiffMpm sim;
  MpmState initial;
};

// A jittered 3×3×3 lattice (spacing 0.05 m, density 1e3) near the corner of a 10³ grid of the unit
// box, so its stencils reach the 3-cell walls of three faces, with random v, C and F near I.
Scene small_scene(torch::ScalarType dtype, uint64_t seed) {
  torch::manual_seed(seed);
  const auto options = torch::TensorOptions().dtype(dtype);
  DiffMpmConfig config;
  config.dx = 0.1;
  config.domain_cells = {10, 10, 10};
  config.fixed_dt = 1e-3;
  const torch::Tensor steps = torch::arange(3, options) * 0.05;
  const std::vector<torch::Tensor> grid = torch::meshgrid({steps, steps, steps}, "ij");
  const torch::Tensor lattice = torch::stack({grid[0].flatten(), grid[1].flatten(), grid[2].flatten()});
  const int64_t n = lattice.size(1);
  const double spacing = 0.05;
  MpmState initial{(0.3 + lattice + 0.01 * torch::rand({3, n}, options)).contiguous(), torch::randn({3, n}, options),
                   3.0 * torch::randn({9, n}, options),
                   (torch::eye(3, options).reshape({9, 1}) + 0.05 * torch::randn({9, n}, options)).contiguous()};
  const torch::Tensor volume = torch::full({n}, spacing * spacing * spacing, options);
  return {DiffMpm(config, 1e3 * volume, volume), initial};
}

// Σ of random weights times every position and velocity and the final v, C, F: a loss that reaches
// every output.
struct RandomLoss {
  RandomLoss(int64_t steps, int64_t n, torch::ScalarType dtype) {
    const auto options = torch::TensorOptions().dtype(dtype);
    positions = torch::randn({steps, 3, n}, options);
    velocities = torch::randn({steps, 3, n}, options);
    v = torch::randn({3, n}, options);
    C = torch::randn({9, n}, options);
    F = torch::randn({9, n}, options);
  }
  torch::Tensor operator()(const Rollout& r) const {
    const MpmState& s = r.final_state;
    return (positions * r.positions).sum() + (velocities * r.velocities).sum() + (v * s.v).sum() + (C * s.C).sum() +
           (F * s.F).sum();
  }
  torch::Tensor positions, velocities, v, C, F;
};

// Checks every `stride`-th entry of `tensor` (all of them by default) with central differences of
// relative step `relative_step`.
void expect_gradient(const char* name, const torch::Tensor& tensor, const std::function<double()>& loss,
                     int64_t stride = 1, double relative_step = 1e-6) {
  ASSERT_TRUE(tensor.grad().defined()) << name;
  const double error = test::finite_difference_error(tensor, tensor.grad(), loss, relative_step, stride);
  std::printf("d loss / d %s: max relative error %.3g\n", name, error);
  EXPECT_LE(error, kGradientTolerance) << "gradient with respect to " << name;
}

TEST(DiffMpm, StepGradientsMatchCentralDifferences) {
  Scene scene = small_scene(torch::kFloat64, 1);
  MpmState state = scene.initial;
  for (torch::Tensor* t : {&state.x, &state.v, &state.C, &state.F}) t->requires_grad_(true);
  const torch::Tensor P = (1e3 * torch::randn({9, scene.sim.particle_count()}, torch::kFloat64)).requires_grad_(true);
  const RandomLoss weights(1, scene.sim.particle_count(), torch::kFloat64);
  const auto loss = [&] {
    const MpmState out = scene.sim.step(state, P);
    return weights({out.x.unsqueeze(0), out.v.unsqueeze(0), out});
  };
  loss().backward();
  const auto value = [&] { return loss().item<double>(); };
  expect_gradient("x", state.x, value);
  expect_gradient("v", state.v, value);
  expect_gradient("C", state.C, value);
  expect_gradient("F", state.F, value);
  // The substep is linear in P (away from the walls), so a larger step costs no truncation error and
  // keeps rounding small: P moves the loss by a tiny fraction of its value.
  expect_gradient("P", P, value, 1, 1e-3);
}

// Five substeps with fixed corotated stress P(F; E, ν) written in LibTorch.
TEST(DiffMpm, RolloutGradientsMatchCentralDifferences) {
  Scene scene = small_scene(torch::kFloat64, 2);
  MpmState& initial = scene.initial;
  for (torch::Tensor* t : {&initial.x, &initial.v, &initial.C, &initial.F}) t->requires_grad_(true);
  const torch::Tensor youngs = torch::tensor(2e4, torch::kFloat64).requires_grad_(true);
  const torch::Tensor poisson = torch::tensor(0.3, torch::kFloat64).requires_grad_(true);
  const ConstitutiveLaws laws{
      [&](const torch::Tensor& F) { return nclaw::fixed_corotated_stress(F, youngs, poisson); }, {}, {}};
  const RolloutOptions options{5, 0};
  const RandomLoss weights(options.steps, scene.sim.particle_count(), torch::kFloat64);
  const auto loss = [&] { return weights(rollout(scene.sim, initial, laws, options)); };
  loss().backward();
  const auto value = [&] { return loss().item<double>(); };
  expect_gradient("x0", initial.x, value);
  expect_gradient("v0", initial.v, value);
  expect_gradient("C0", initial.C, value);
  expect_gradient("F0", initial.F, value);
  expect_gradient("E", youngs, value);
  expect_gradient("nu", poisson, value);
}

// Both neural laws in the loop (Alg. 2): gradients reach the first layer of each network.
TEST(DiffMpm, NeuralLawRolloutGradientsMatchCentralDifferences) {
  Scene scene = small_scene(torch::kFloat64, 3);
  const nclaw::NeuralLaws laws_in_double = nclaw::seeded_laws(3, torch::kFloat64);
  nclaw::ElasticLaw elastic = laws_in_double.elastic;
  nclaw::PlasticLaw plastic = laws_in_double.plastic;
  // Untrained weights give stresses of order 1 Pa and plastic corrections of order 1e-5; scale both
  // laws' last layers so that they move the particles within five substeps, and their gradients
  // stand well above the central differences' rounding of the loss.
  {
    torch::NoGradGuard no_grad;
    elastic->parameters().back().mul_(1e4);
    plastic->parameters().back().mul_(1e2);
  }
  const ConstitutiveLaws laws{[&](const torch::Tensor& F) { return elastic->forward(F); },
                              [&](const torch::Tensor& F) { return plastic->forward(F); },
                              {}};
  const RolloutOptions options{5, 0};
  const RandomLoss weights(options.steps, scene.sim.particle_count(), torch::kFloat64);
  const auto loss = [&] { return weights(rollout(scene.sim, scene.initial, laws, options)); };
  loss().backward();
  const auto value = [&] { return loss().item<double>(); };
  // 60 of the 832 weights of each first layer: every 14th, which cycles through the 13 inputs.
  expect_gradient("elastic first layer", elastic->parameters().front(), value, 14);
  expect_gradient("plastic first layer", plastic->parameters().front(), value, 14);
}

// Recomputing segments of 2 substeps from checkpoints gives the full graph's loss and gradients.
TEST(DiffMpm, CheckpointedRolloutMatchesFullGraph) {
  Scene scene = small_scene(torch::kFloat64, 4);
  const nclaw::NeuralLaws laws_in_double = nclaw::seeded_laws(4, torch::kFloat64);
  nclaw::ElasticLaw elastic = laws_in_double.elastic;
  nclaw::PlasticLaw plastic = laws_in_double.plastic;
  const torch::Tensor log_youngs = torch::tensor(std::log(2e4), torch::kFloat64).requires_grad_(true);
  scene.initial.v.requires_grad_(true);
  const RandomLoss weights(7, scene.sim.particle_count(), torch::kFloat64);

  std::vector<torch::Tensor> parameters = elastic->parameters();
  for (const torch::Tensor& p : plastic->parameters()) parameters.push_back(p);
  parameters.push_back(log_youngs);
  std::vector<torch::Tensor> results[2];
  for (int checkpoint_every : {0, 2}) {
    for (torch::Tensor& p : parameters) p.mutable_grad() = torch::Tensor();
    scene.initial.v.mutable_grad() = torch::Tensor();
    // E enters through a non-leaf tensor, which checkpointed segments must differentiate too.
    const torch::Tensor youngs = log_youngs.exp();
    const ConstitutiveLaws laws{[&](const torch::Tensor& F) {
      return elastic->forward(F) + nclaw::fixed_corotated_stress(F, youngs, torch::tensor(0.3, torch::kFloat64));
                                },
                                [&](const torch::Tensor& F) { return plastic->forward(F); },
                                {elastic->parameters()[0], elastic->parameters()[1], elastic->parameters()[2],
                                 plastic->parameters()[0], plastic->parameters()[1], plastic->parameters()[2], youngs}};
    const torch::Tensor loss = weights(rollout(scene.sim, scene.initial, laws, {7, checkpoint_every}));
    loss.backward();
    std::vector<torch::Tensor>& result = results[checkpoint_every == 0 ? 0 : 1];
    result.push_back(loss.detach());
    result.push_back(scene.initial.v.grad().clone());
    for (const torch::Tensor& p : parameters) result.push_back(p.grad().clone());
  }
  for (size_t i = 0; i < results[0].size(); ++i)
    EXPECT_TRUE(torch::allclose(results[1][i], results[0][i], 1e-10, 1e-12 * results[0][i].abs().max().item<double>()))
        << "result " << i;
}

// The training scene of Ma et al. 2023 in float: 1000 particles in a cube thrown into the unit box,
// both neural laws, a short rollout and its backward pass.
TEST(DiffMpm, FloatTrainingSceneRunsForwardAndBackward) {
  torch::manual_seed(5);
  const torch::Tensor side = torch::arange(10, torch::kFloat32) * 0.05 + 0.275;
  const std::vector<torch::Tensor> grid = torch::meshgrid({side, side, side}, "ij");
  const torch::Tensor x = torch::stack({grid[0].flatten(), grid[1].flatten(), grid[2].flatten()}).contiguous();
  const int64_t n = x.size(1);
  const torch::Tensor volume = torch::full({n}, 0.125f / float(n));
  const DiffMpm sim(DiffMpmConfig{}, 1e3 * volume, volume);
  const torch::Tensor omega = torch::tensor({4.0f, 4.0f, 4.0f}).reshape({3, 1});
  const torch::Tensor arm = x - 0.5f;
  const torch::Tensor v =
      (torch::tensor({1.0f, -1.5f, -2.0f}).reshape({3, 1}) + torch::cross(omega.expand({3, n}), arm, 0))
          .contiguous()
          .requires_grad_(true);
  const MpmState initial{x, v, torch::zeros({9, n}), torch::eye(3).reshape({9, 1}).expand({9, n}).contiguous()};
  nclaw::ElasticLaw elastic;
  nclaw::PlasticLaw plastic;
  const ConstitutiveLaws laws{[&](const torch::Tensor& F) { return elastic->forward(F); },
                              [&](const torch::Tensor& F) { return plastic->forward(F); },
                              {}};
  const Rollout result = rollout(sim, initial, laws, {20, 0});
  EXPECT_TRUE(torch::isfinite(result.positions).all().item<bool>());
  (1e4 * (result.positions - x.unsqueeze(0)).square().mean()).backward();
  EXPECT_TRUE(torch::isfinite(v.grad()).all().item<bool>());
  for (const torch::Tensor& p : elastic->parameters()) EXPECT_TRUE(torch::isfinite(p.grad()).all().item<bool>());
  for (const torch::Tensor& p : plastic->parameters()) EXPECT_TRUE(torch::isfinite(p.grad()).all().item<bool>());
}

TEST(DiffMpm, RejectsMismatchedTensors) {
  const Scene scene = small_scene(torch::kFloat64, 6);
  MpmState state = scene.initial;
  state.F = state.F.to(torch::kFloat32);
  EXPECT_THROW(scene.sim.step(state, torch::zeros({9, scene.sim.particle_count()}, torch::kFloat64)), Error);
  EXPECT_THROW(scene.sim.step(scene.initial, torch::zeros({9, 5}, torch::kFloat64)), Error);
}

// The same step on a CUDA device as on the CPU (skipped where LibTorch has no CUDA device).
TEST(DiffMpm, CudaStepMatchesCpu) {
  if (!torch::cuda::is_available()) GTEST_SKIP() << "LibTorch reports no CUDA device";
  const Scene scene = small_scene(torch::kFloat64, 7);
  const torch::Device cuda(torch::kCUDA);
  const DiffMpm sim_cuda(scene.sim.config(), scene.sim.mass().to(cuda), scene.sim.volume().to(cuda));
  const MpmState& s = scene.initial;
  const torch::Tensor P = 1e3 * torch::randn({9, scene.sim.particle_count()}, torch::kFloat64);
  const MpmState cpu = scene.sim.step(s, P);
  const MpmState gpu = sim_cuda.step({s.x.to(cuda), s.v.to(cuda), s.C.to(cuda), s.F.to(cuda)}, P.to(cuda));
  EXPECT_TRUE(torch::allclose(gpu.x.cpu(), cpu.x, 1e-12, 1e-12));
  EXPECT_TRUE(torch::allclose(gpu.v.cpu(), cpu.v, 1e-12, 1e-12));
  EXPECT_TRUE(torch::allclose(gpu.C.cpu(), cpu.C, 1e-10, 1e-10));
  EXPECT_TRUE(torch::allclose(gpu.F.cpu(), cpu.F, 1e-12, 1e-12));
}

}  // namespace
}  // namespace romp::nn::diffmpm
