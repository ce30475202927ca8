// A reduced-order model as training leaves it and the model file keeps it: the deformation map g, the encoder e
// with the material points it reads, and the record of the data and settings it was trained with.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "nn/rom/deformation_map.h"
#include "nn/rom/encoder.h"
#include "nn/rom/manifold_derivatives.h"
#include "nn/rom/rom_dataset.h"
#include "nn/rom/rom_loss.h"

namespace romp::nn::rom {

// Everything that decides a training run's result (with the data). A resumed run must use the same settings.
struct TrainingSettings {
  MapArchitecture architecture;        // latent r, hidden layers (0: the linear baseline), width
  std::int64_t encoder_points = 1000;  // Q (0: every point)
  std::int64_t epochs = 1000;
  std::int64_t batch = 16;    // snapshots per mini-batch
  std::int64_t points = 256;  // material points per snapshot in the loss, drawn anew each batch
  std::uint64_t seed = 0;
  LossWeights loss_weights;
  double learning_rate = 1e-3;  // the first stage's
  // Fractions of the epochs after which the learning rate drops tenfold: 1e-3 → 1e-4 → 1e-5 → 1e-6.
  std::vector<double> decay_at = {0.5, 0.75, 0.9};
  DerivativeMethod derivatives = DerivativeMethod::Analytic;

  // The learning rate of epoch `epoch` (0-based).
  double learning_rate_at(std::int64_t epoch) const;
  // "batch: 16 here, 32 in the other" for each setting that differs; empty when they agree.
  std::vector<std::string> differences(const TrainingSettings& other) const;
};

// Relative L2 errors over every point of every snapshot of a set, as the paper's position error (Sec. 5):
// ‖prediction − truth‖ / ‖truth‖, summed over points and snapshots. NaN where the set is empty (or the truth 0).
struct ReconstructionErrors {
  double position = std::numeric_limits<double>::quiet_NaN();
  double F = std::numeric_limits<double>::quiet_NaN();
  // (∂g/∂x̂)(x̂_{n+1} − x̂_n)/Δt against (x_{n+1} − x_n)/Δt; last frames excluded
  double velocity = std::numeric_limits<double>::quiet_NaN();
};

struct TrainingRecord {
  std::string sweep_dir;
  std::vector<std::string> parameter_names;
  std::vector<SweepMember> members;
  std::int64_t particle_count = 0;  // P of the training snapshots (the encoder's indices point into them)
  TrainingSettings settings;
  std::int64_t epochs_done = 0;
  ReconstructionErrors train_errors, test_errors;
  std::string romp_version, commit;  // of the romp that trained it
};

struct RomModel {
  DeformationMap map{nullptr};
  Encoder encoder{nullptr};
  torch::Tensor encoder_indices;  // [Q] i64, increasing: the material points (initial order) the encoder reads
  TrainingRecord training;

  // x̂ of B snapshots from the positions of all their material points, x [B, P, 3] → [B, r].
  torch::Tensor encode(const torch::Tensor& x) const;
  // The trainable tensors, map first, in a fixed order (checkpoints store the optimiser's moments in it).
  std::vector<torch::Tensor> parameters() const;
  // Moves both networks and the indices to `device`.
  void to(const torch::Device& device);
};

// A freshly initialised model for `data` (normalisation from its training split), drawn from torch's global
// generator after seeding it with settings.seed.
RomModel initial_model(const RomDataset& data, const TrainingSettings& settings);

}  // namespace romp::nn::rom
