// The per-epoch schedules of neural-law training (Ma et al. 2023, App. D.2): cosine-annealed learning
// rates and teacher-forcing period.
#pragma once

#include <cstdint>

namespace romp::nn::nclaw {

// Cosine annealing from `first` at epoch 0 to `last` at epoch `epochs`, as PyTorch's
// CosineAnnealingLR with T_max = epochs: last + (first − last)(1 + cos(π epoch / epochs)) / 2.
double cosine_anneal(double first, double last, int64_t epoch, int64_t epochs);

// The teacher-forcing period of an epoch: the rollout restarts from the ground truth every so many
// substeps, cosine-scheduled from `first` (25 in the paper) up to `last` (200), rounded.
int64_t teacher_forcing_period(int64_t first, int64_t last, int64_t epoch, int64_t epochs);

}  // namespace romp::nn::nclaw
