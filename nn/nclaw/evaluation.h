// The evaluation metric of Ma et al. 2023 (Sec. 4.1): position error of a free rollout against a trajectory.
#pragma once

#include <cstdint>

#include "nn/diffmpm/mpm_step.h"
#include "nn/diffmpm/rollout.h"
#include "nn/nclaw/trajectory.h"

namespace romp::nn::nclaw {

// "the average mean square error every 5 frames" (Sec. 4.1).
inline constexpr int64_t kEvaluationFrameStride = 5;

// The mean over frames every, 2 every, … ≤ steps of MSE(x, x_gt) (over particles and axes) of a
// rollout of `laws` from frame 0 of `truth`, without teacher forcing and without gradients.
double position_error(const diffmpm::DiffMpm& sim, const Trajectory& truth, const diffmpm::ConstitutiveLaws& laws,
                      int64_t steps, int64_t every = kEvaluationFrameStride);

}  // namespace romp::nn::nclaw
