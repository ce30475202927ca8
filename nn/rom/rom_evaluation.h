// Reconstruction errors of a trained ROM on full-order snapshots: every material point of every snapshot is
// mapped through e and g and compared in position, deformation gradient and velocity.
#pragma once

#include <torch/torch.h>

#include "nn/rom/rom_dataset.h"
#include "nn/rom/rom_model.h"

namespace romp::nn::rom {

// Rows (material points × snapshots) evaluated at once; bounds the memory of the tangents, [4, rows, width].
inline constexpr std::int64_t kEvaluationRows = std::int64_t(1) << 16;

// Relative L2 errors of `model` on `set`, whose snapshots have reference positions X [P, 3] (on the set's
// device). Velocities are (∂g/∂x̂)(x̂_{n+1} − x̂_n)/Δt as in Eq. (31), so last frames do not count for them.
ReconstructionErrors reconstruction_errors(const RomModel& model, const torch::Tensor& X, const SnapshotSet& set,
                                           DerivativeMethod method = DerivativeMethod::Analytic);

}  // namespace romp::nn::rom
