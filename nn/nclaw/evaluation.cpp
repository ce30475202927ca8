// position_error: one free rollout, compared every `every` frames.
#include "nn/nclaw/evaluation.h"

#include <string>

#include "kernels/core/error.h"

namespace romp::nn::nclaw {

double position_error(const diffmpm::DiffMpm& sim, const Trajectory& truth, const diffmpm::ConstitutiveLaws& laws,
                      int64_t steps, int64_t every) {
  ROMP_CHECK(every > 0 && every <= steps, "position error: frame stride must be in [1, steps = " +
                                              std::to_string(steps) + "], got " + std::to_string(every));
  truth.require_steps(steps, "position error");
  torch::NoGradGuard no_grad;
  const diffmpm::Rollout result = diffmpm::rollout(sim, truth.state(0), laws, {steps, 0});
  // positions[s] is frame s + 1.
  const torch::Tensor predicted = result.positions.slice(0, every - 1, steps, every);
  const torch::Tensor expected = truth.x.slice(0, every, steps + 1, every);
  return (predicted - expected).square().mean({1, 2}).mean().item<double>();
}

}  // namespace romp::nn::nclaw
