// LawTrainer: learns neural elastic and plastic laws from a ground-truth trajectory by backpropagating
// a position loss through the differentiable MPM (Ma et al. 2023, Sec. 3 and App. D.2).
#pragma once

#include <torch/torch.h>

#include <memory>
#include <string>
#include <vector>

#include "nn/diffmpm/mpm_step.h"
#include "nn/nclaw/neural_laws.h"
#include "nn/nclaw/trajectory.h"

namespace romp::nn::nclaw {

// The authors' protocol; every default is theirs (velocity_weight = 0 leaves their loss as it is).
struct TrainingOptions {
  int64_t epochs = 300;                // one rollout each; the cosine schedules span them all
  int64_t steps = 1000;                // substeps per rollout (the trajectory needs steps + 1 frames)
  double elastic_learning_rate = 1.0;  // Adam
  double plastic_learning_rate = 0.1;
  double gradient_clip = 0.1;          // largest gradient norm, per network
  double loss_scale = 1e4;             // loss = Σ_steps loss_scale · MSE(x, x_gt)
  int64_t teacher_forcing_first = 25;  // restart period (substeps) at the first epoch ...
  int64_t teacher_forcing_last = 200;  // ... rising to this one by cosine annealing
  uint64_t seed = 0;                   // initial weights (Xavier uniform)
  int64_t checkpoint_every = 0;        // > 0: recompute each segment from states this many substeps apart
  double velocity_weight = 0.0;        // beyond App. D.2: the velocity penalty of App. Table 7 (TrajectoryLossOptions)

  // Throws romp::Error naming the first option out of range.
  void validate() const;
};

// What one epoch did.
struct EpochReport {
  int64_t epoch = 0;                   // 0-based index of the epoch just trained
  double loss = 0.0;                   // of the rollout before the update
  double elastic_gradient_norm = 0.0;  // before clipping
  double plastic_gradient_norm = 0.0;
  double elastic_learning_rate = 0.0;  // used for this epoch's update
  double plastic_learning_rate = 0.0;
  int64_t teacher_forcing_period = 0;
  double seconds = 0.0;           // wall time of the epoch: ...
  double forward_seconds = 0.0;   // ... the rollouts and their loss graphs,
  double backward_seconds = 0.0;  // ... their backward passes (the rest: clipping, Adam)
};

class LawTrainer {
 public:
  // The laws and the simulation run on the trajectory's device and dtype (float32 for training).
  LawTrainer(const diffmpm::DiffMpmConfig& config, Trajectory truth, const TrainingOptions& options);

  // One rollout of options.steps substeps with teacher forcing, its backward pass segment by
  // segment, per-network clipping and one Adam step of each network.
  EpochReport train_epoch();

  int64_t epochs_done() const { return int64_t(losses_.size()); }
  bool finished() const { return epochs_done() >= options_.epochs; }
  // The loss of every epoch so far.
  const std::vector<double>& losses() const { return losses_; }
  const NeuralLaws& laws() const { return laws_; }
  // The reconstruction error of the laws as they are now: position_error (nn/nclaw/evaluation.h)
  // of a free rollout of options.steps substeps against the training trajectory.
  double reconstruction_error() const;
  const TrainingOptions& options() const { return options_; }

  // Everything training needs to continue bitwise as if uninterrupted: weights, Adam moments,
  // losses, options. Written to a temporary name and renamed, so a crash keeps the previous one.
  void save_checkpoint(const std::string& path) const;
  // Restores a checkpoint of a trainer with the same options; throws romp::Error naming the file
  // when it is unreadable or was written with other options.
  void load_checkpoint(const std::string& path);

 private:
  diffmpm::DiffMpm sim_;
  Trajectory truth_;
  TrainingOptions options_;
  NeuralLaws laws_;
  std::unique_ptr<torch::optim::Adam> elastic_optimizer_, plastic_optimizer_;
  std::vector<double> losses_;
};

}  // namespace romp::nn::nclaw
