// Trajectory: a ground-truth motion in engine planes, one frame per substep, as training and evaluation read it.
#pragma once

#include <torch/torch.h>

#include <string>

#include "nn/diffmpm/mpm_step.h"
#include "nn/diffmpm/rollout.h"

namespace romp::nn::nclaw {

// Frame k is the state after k substeps; frame 0 is the initial state. Tensors share one dtype and
// device: mass, volume [n]; x, v [frames, 3, n]; C, F [frames, 9, n].
struct Trajectory {
  torch::Tensor mass, volume;
  torch::Tensor x, v, C, F;

  int64_t frame_count() const { return x.size(0); }
  int64_t particle_count() const { return mass.size(0); }
  diffmpm::MpmState state(int64_t frame) const { return {x[frame], v[frame], C[frame], F[frame]}; }
  // Throws romp::Error naming the first field whose shape, dtype or device disagrees with mass.
  void validate() const;
  // Throws romp::Error, starting with `who`, unless frames 0 .. steps exist.
  void require_steps(int64_t steps, const std::string& who) const;
  Trajectory to(const torch::Device& device, torch::ScalarType dtype) const;
};

// The trajectory of `steps` substeps from `initial` under `laws`, without gradients: ground truth
// from a known law (tests, benchmarks, the oracles), or a learned law's prediction.
Trajectory simulate(const diffmpm::DiffMpm& sim, const diffmpm::MpmState& initial,
                    const diffmpm::ConstitutiveLaws& laws, int64_t steps);

}  // namespace romp::nn::nclaw
