// The training loss of Ma et al. 2023 (App. D.2): positions of a rollout against a ground-truth
// trajectory (and, optionally, velocities: App. Table 7), with teacher forcing, backpropagated segment
// by segment.
#pragma once

#include <cstdint>

#include "nn/diffmpm/mpm_step.h"
#include "nn/diffmpm/rollout.h"
#include "nn/nclaw/trajectory.h"

namespace romp::nn::nclaw {

struct TrajectoryLossOptions {
  int64_t steps = 1000;                 // substeps compared with frames 1 .. steps
  int64_t teacher_forcing_period = 25;  // the rollout restarts from the ground truth this often
  double loss_scale = 1e4;       // loss = Σ_steps loss_scale · (MSE(x, x_gt) + velocity_weight · MSE(v, v_gt))
  int64_t checkpoint_every = 0;  // see diffmpm::RolloutOptions
  // The velocity-dissimilarity penalty of the paper's App. Table 7 (s²; 0 = positions only, App. D.2).
  double velocity_weight = 0.0;
};

// The loss and where its time went: the rollouts with their loss graphs, and their backward passes
// (wall time, each phase waited for on the device, so both hold on a GPU too).
struct TrajectoryLossResult {
  double value = 0.0;
  double forward_seconds = 0.0;
  double backward_seconds = 0.0;
};

// The loss of options.steps substeps of `laws` from frame 0 of `truth`, restarted from the ground
// truth every teacher_forcing_period substeps. Gradients are accumulated into whatever the laws
// read: each segment goes backward as soon as its loss is known (no gradient crosses a restart),
// so only one segment's graph is held at a time.
TrajectoryLossResult backpropagate_trajectory_loss(const diffmpm::DiffMpm& sim, const Trajectory& truth,
                                                   const diffmpm::ConstitutiveLaws& laws,
                                                   const TrajectoryLossOptions& options);

}  // namespace romp::nn::nclaw
