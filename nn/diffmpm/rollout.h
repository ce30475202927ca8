// Differentiable rollouts: MPM substeps with the constitutive laws between them, optionally recomputed from
// checkpoints.
#pragma once

#include <torch/torch.h>

#include <functional>
#include <vector>

#include "nn/diffmpm/mpm_step.h"

namespace romp::nn::diffmpm {

// The constitutive laws of a rollout (Ma et al. 2023, Alg. 2): P = elastic(F) before each substep,
// F = plastic(F_trial) after it. Both map [9, n] planes to [9, n] planes.
struct ConstitutiveLaws {
  std::function<torch::Tensor(const torch::Tensor&)> elastic;
  std::function<torch::Tensor(const torch::Tensor&)> plastic;  // empty: no plasticity, F = F_trial
  // Every tensor the laws read that gradients must reach (network weights, E, ν). Needed only with
  // checkpoints, where the recomputed segments differentiate with respect to them explicitly.
  std::vector<torch::Tensor> parameters;
};

struct RolloutOptions {
  int64_t steps = 1000;
  // 0 keeps every substep's graph (particle states, the laws' activations) for the backward pass.
  // k > 0 keeps only the state every k substeps and rebuilds each segment's graph while going
  // backward: memory O(steps / k + k) states instead of O(steps), for one extra forward pass.
  int64_t checkpoint_every = 0;
};

struct Rollout {
  torch::Tensor positions;   // [steps, 3, n]: x after each substep
  torch::Tensor velocities;  // [steps, 3, n]: v after each substep
  MpmState final_state;
};

// Runs options.steps substeps from `initial`. The laws must stay valid until the backward pass of
// anything computed from the result has run.
Rollout rollout(const DiffMpm& sim, const MpmState& initial, const ConstitutiveLaws& laws,
                const RolloutOptions& options);

}  // namespace romp::nn::diffmpm
