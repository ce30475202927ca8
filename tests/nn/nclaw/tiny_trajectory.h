// A tiny ground truth for training tests: a 4³-particle jelly cube dropped onto the floor of a 10³ grid,
// simulated by the differentiable step itself with fixed corotated stress (E = 1e4 Pa, ν = 0.3).
#pragma once

#include <torch/torch.h>

#include <vector>

#include "nn/diffmpm/mpm_step.h"
#include "nn/diffmpm/rollout.h"
#include "nn/nclaw/fixed_corotated.h"
#include "nn/nclaw/trajectory.h"

namespace romp::nn::test {

struct TinyGroundTruth {
  diffmpm::DiffMpmConfig config;
  nclaw::Trajectory trajectory;
};

inline TinyGroundTruth tiny_ground_truth(int64_t steps) {
  torch::NoGradGuard no_grad;
  const auto f32 = torch::TensorOptions().dtype(torch::kFloat32);
  diffmpm::DiffMpmConfig config;
  config.dx = 0.1;
  config.domain_cells = {10, 10, 10};
  config.fixed_dt = 1e-3;
  const torch::Tensor side = torch::arange(4, f32) * 0.05f + 0.425f;
  const std::vector<torch::Tensor> grid = torch::meshgrid({side, side, side}, "ij");
  torch::Tensor x = torch::stack({grid[0].flatten(), grid[1].flatten(), grid[2].flatten()}).contiguous();
  x[1] -= 0.05f;  // bottom layer at y = 0.325, just above the 3-cell floor
  const int64_t n = x.size(1);
  const torch::Tensor volume = torch::full({n}, 0.05f * 0.05f * 0.05f, f32);
  const diffmpm::DiffMpm sim(config, 1e3 * volume, volume);
  const torch::Tensor v = torch::tensor({0.5f, -2.0f, 0.3f}, f32).reshape({3, 1}).expand({3, n}).contiguous();
  const diffmpm::MpmState initial{x, v, torch::zeros({9, n}, f32),
                                  torch::eye(3, f32).reshape({9, 1}).expand({9, n}).contiguous()};
  const torch::Tensor youngs = torch::tensor(1e4, f32), poisson = torch::tensor(0.3, f32);
  const diffmpm::ConstitutiveLaws law{
      [&](const torch::Tensor& F) { return nclaw::fixed_corotated_stress(F, youngs, poisson); }, {}, {}};
  return {config, nclaw::simulate(sim, initial, law, steps)};
}

}  // namespace romp::nn::test
