// The training loss of the ROM paper, Eq. (31): position error, plus λ_F times the deformation-gradient error,
// plus λ_v times the error of the velocity (∂g/∂x̂)(x̂_{n+1} − x̂_n)/Δt, averaged over material points. The
// paper's target is φ̇(t_n); romp's is the frames' own difference (x_{n+1} − x_n)/Δt, which is φ̇ when frames
// are one substep apart (the MPM moves x by Δt·v_{n+1}) and, for frames several substeps apart, leaves in the
// term only the linearisation error it is there to reduce (SnapshotSet::frame_velocity).
//
// Eq. (31) depends on the length unit: in metres a 4 cm cylinder's position errors are ~1e-5 while F's are
// O(1e-2), and λ_F = 100 leaves the positions unlearnt (measured: 20% test position error after 3 epochs of
// the gravity sweep). romp measures position and velocity errors in units of the training displacements'
// spread ‖u_std‖ (one length for all components, so the loss stays rotation invariant and a component that
// hardly moves does not dominate), and the paper's weights mean the same for any body size and unit.
#pragma once

#include <torch/torch.h>

#include "nn/rom/deformation_map.h"
#include "nn/rom/manifold_derivatives.h"
#include "nn/rom/training_record.h"

namespace romp::nn::rom {

// One mini-batch flattened to N rows (material point p of snapshot s, frame n of its member).
struct LossBatch {
  torch::Tensor xhat;       // [N, r] x̂ of the row's snapshot, from the encoder
  torch::Tensor xhat_rate;  // [N, r] (x̂_{n+1} − x̂_n) / Δt, zero where frame n+1 does not exist
  torch::Tensor X;          // [N, 3] reference positions
  torch::Tensor x;          // [N, 3] full-order positions
  torch::Tensor v;          // [N, 3] the frames' velocity (x_{n+1} − x_n)/Δt (SnapshotSet::frame_velocity)
  torch::Tensor F;          // [N, 3, 3] full-order deformation gradients
  torch::Tensor has_next;   // [N] 1 where frame n+1 exists (the velocity term counts), else 0
};

// Scalar tensors: total = position + λ_F·F + λ_v·velocity, each term a mean over its rows of a squared
// (Frobenius) norm, position and velocity errors divided by ‖u_std‖; the velocity term over the rows with
// has_next only.
struct LossTerms {
  torch::Tensor total, position, F, velocity;
};

LossTerms rom_loss(const DeformationMapImpl& g, const LossBatch& batch, const LossWeights& weights,
                   DerivativeMethod method);

}  // namespace romp::nn::rom
