// SystemIdentification: the oracle of Ma et al. 2023 (Sec. 4) that knows the true model and learns
// only its parameters: Young's modulus E and Poisson's ratio ν of fixed corotated elasticity,
// fitted to a trajectory through the same differentiable simulation and loss as the neural laws.
#pragma once

#include <torch/torch.h>

#include <memory>

#include "nn/diffmpm/mpm_step.h"
#include "nn/nclaw/trajectory.h"

namespace romp::nn::nclaw {

struct SystemIdentificationOptions {
  int64_t epochs = 100;                // one rollout each; the cosine schedules span them all
  int64_t steps = 1000;                // substeps per rollout
  double learning_rate = 0.3;          // Adam, on log E and logit(2ν)
  int64_t teacher_forcing_first = 25;  // as TrainingOptions
  int64_t teacher_forcing_last = 200;
  double loss_scale = 1e4;
  double initial_youngs = 1e5;    // Pa
  double initial_poisson = 0.25;  // in (0, 0.5)

  // Throws romp::Error naming the first option out of range.
  void validate() const;
};

class SystemIdentification {
 public:
  SystemIdentification(const diffmpm::DiffMpmConfig& config, Trajectory truth,
                       const SystemIdentificationOptions& options);

  // One rollout with teacher forcing and one Adam step; returns the loss before the step.
  double train_epoch();

  int64_t epochs_done() const { return epochs_done_; }
  bool finished() const { return epochs_done_ >= options_.epochs; }
  double youngs() const;  // Pa
  double poisson() const;

 private:
  // E = exp(log_youngs) > 0 and ν = sigmoid(poisson_logit) / 2 in (0, 0.5) for any parameter values.
  torch::Tensor youngs_tensor() const;
  torch::Tensor poisson_tensor() const;

  diffmpm::DiffMpm sim_;
  Trajectory truth_;
  SystemIdentificationOptions options_;
  torch::Tensor log_youngs_, poisson_logit_;
  std::unique_ptr<torch::optim::Adam> optimizer_;
  int64_t epochs_done_ = 0;
};

}  // namespace romp::nn::nclaw
