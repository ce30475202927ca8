// backpropagate_trajectory_loss: teacher-forced segments, each rolled out and differentiated in turn.
#include "nn/nclaw/trajectory_loss.h"

#include <algorithm>
#include <string>

#include "kernels/core/error.h"

namespace romp::nn {

double backpropagate_trajectory_loss(const DiffMpm& sim, const Trajectory& truth, const ConstitutiveLaws& laws,
                                     const TrajectoryLossOptions& options) {
  ROMP_CHECK(options.teacher_forcing_period > 0, "trajectory loss: teacher_forcing_period must be positive, got " +
                                                     std::to_string(options.teacher_forcing_period));
  ROMP_CHECK(options.velocity_weight >= 0.0,
             "trajectory loss: velocity_weight must be >= 0, got " + std::to_string(options.velocity_weight));
  truth.require_steps(options.steps, "trajectory loss");
  double total = 0.0;
  for (int64_t start = 0; start < options.steps; start += options.teacher_forcing_period) {
    const int64_t steps = std::min(options.teacher_forcing_period, options.steps - start);
    const Rollout result = rollout(sim, truth.state(start), laws, {steps, options.checkpoint_every});
    // Frames start + 1 .. start + steps; MSE over particles and axes per substep, summed over the substeps.
    const auto mse = [&](const torch::Tensor& predicted, const torch::Tensor& truth_frames) {
      return (predicted - truth_frames.slice(0, start + 1, start + 1 + steps)).square().mean({1, 2}).sum();
    };
    torch::Tensor mismatch = mse(result.positions, truth.x);
    if (options.velocity_weight > 0.0) mismatch = mismatch + options.velocity_weight * mse(result.velocities, truth.v);
    const torch::Tensor loss = options.loss_scale * mismatch;
    loss.backward();
    total += loss.item<double>();
  }
  return total;
}

}  // namespace romp::nn
