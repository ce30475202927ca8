// The rotation-invariant inputs and the rotation of the neural constitutive laws (Ma et al. 2023, Alg. 4 lines 1–3).
#pragma once

#include <torch/torch.h>

namespace romp::nn::nclaw {

// [9, n] engine planes as [n, 3, 3] matrices, and back (contiguous copies).
torch::Tensor planes_to_matrices(const torch::Tensor& planes);
torch::Tensor matrices_to_planes(const torch::Tensor& matrices);

struct StretchRotation {
  torch::Tensor sigma;  // [n, 3] signed singular values: σ₀ ≥ σ₁ ≥ |σ₂|, σ₂ < 0 where det F < 0
  torch::Tensor R;      // [n, 3, 3] the polar rotation U Vᵀ, a proper rotation also for inverted F
};

// σ and R of F [9, n] (planes) from romp's batched SVD, differentiable: the backward pass adds the SVD's
// dσ part (exact, no gap terms) and the polar rotation's (only σᵢ + σⱼ gaps, smooth through repeated
// singular values), both from nn/svd_ops.h, so F = I and other isotropic states get finite gradients.
StretchRotation stretch_and_rotation(const torch::Tensor& F);

// The 13 network inputs [n, 13] of the authors' code: σ − 1 (3), FᵀF − I (9, row-major), det F − 1.
// All three are invariant under F → Q F (Ma et al. 2023, App. C.2) and exactly zero at F = I.
torch::Tensor invariant_features(const torch::Tensor& F, const torch::Tensor& sigma);

}  // namespace romp::nn::nclaw
