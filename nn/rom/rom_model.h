// A reduced-order model as training leaves it and the model file keeps it: the deformation map g, the encoder e
// with the material points it reads, and the record of the data and settings it was trained with.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <string>
#include <vector>

#include "nn/rom/deformation_map.h"
#include "nn/rom/encoder.h"
#include "nn/rom/manifold_derivatives.h"
#include "nn/rom/rom_dataset.h"
#include "nn/rom/rom_loss.h"
#include "nn/rom/training_record.h"

namespace romp::nn::rom {

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
