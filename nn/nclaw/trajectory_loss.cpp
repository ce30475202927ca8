// backpropagate_trajectory_loss: teacher-forced segments, each rolled out and differentiated in turn.
#include "nn/nclaw/trajectory_loss.h"

#include <algorithm>
#include <chrono>
#include <string>

#include "kernels/core/error.h"
#include "nn/tensor_bridge.h"

namespace romp::nn::nclaw {

TrajectoryLossResult backpropagate_trajectory_loss(const diffmpm::DiffMpm& sim, const Trajectory& truth,
                                                   const diffmpm::ConstitutiveLaws& laws,
                                                   const TrajectoryLossOptions& options) {
  ROMP_CHECK(options.teacher_forcing_period > 0, "trajectory loss: teacher_forcing_period must be positive, got " +
                                                     std::to_string(options.teacher_forcing_period));
  ROMP_CHECK(options.velocity_weight >= 0.0,
             "trajectory loss: velocity_weight must be >= 0, got " + std::to_string(options.velocity_weight));
  truth.require_steps(options.steps, "trajectory loss");
  const Exec device = exec_for(truth.x);
  const auto seconds_since = [&](std::chrono::steady_clock::time_point& mark) {
    synchronize(device);
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - mark).count();
    mark = now;
    return elapsed;
  };
  TrajectoryLossResult total;
  auto mark = std::chrono::steady_clock::now();
  for (int64_t start = 0; start < options.steps; start += options.teacher_forcing_period) {
    const int64_t steps = std::min(options.teacher_forcing_period, options.steps - start);
    const diffmpm::Rollout result = diffmpm::rollout(sim, truth.state(start), laws, {steps, options.checkpoint_every});
    // Frames start + 1 .. start + steps; MSE over particles and axes per substep, summed over the substeps.
    const auto mse = [&](const torch::Tensor& predicted, const torch::Tensor& truth_frames) {
      return (predicted - truth_frames.slice(0, start + 1, start + 1 + steps)).square().mean({1, 2}).sum();
    };
    torch::Tensor mismatch = mse(result.positions, truth.x);
    if (options.velocity_weight > 0.0) mismatch = mismatch + options.velocity_weight * mse(result.velocities, truth.v);
    const torch::Tensor loss = options.loss_scale * mismatch;
    total.forward_seconds += seconds_since(mark);
    loss.backward();
    total.value += loss.item<double>();
    total.backward_seconds += seconds_since(mark);
  }
  return total;
}

}  // namespace romp::nn::nclaw
