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
// `points` > 0 compares g at about that many evenly spaced material points of each snapshot instead of all
// P (the encoder still reads whole snapshots): an estimate for progress reports at a fraction of the cost.
ReconstructionErrors reconstruction_errors(const RomModel& model, const torch::Tensor& X, const SnapshotSet& set,
                                           DerivativeMethod method = DerivativeMethod::Analytic,
                                           std::int64_t points = 0);

// The stride between the material points compared when asking for `points` of `particles` (0: all), and
// how many that compares.
inline std::int64_t evaluation_stride(std::int64_t particles, std::int64_t points) {
  return points > 0 && points < particles ? (particles + points - 1) / points : 1;
}
inline std::int64_t evaluated_points(std::int64_t particles, std::int64_t points) {
  const std::int64_t stride = evaluation_stride(particles, points);
  return (particles + stride - 1) / stride;
}

}  // namespace romp::nn::rom
