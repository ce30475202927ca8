// Fixed corotated elasticity in LibTorch, differentiable in F, E and ν: the analytic law for gradient checks and
// oracles.
#pragma once

#include <torch/torch.h>

namespace romp::nn::nclaw {

// P = 2μ (F − R) + λ (J − 1) J F⁻ᵀ (Ma et al. 2023, App. B, Eq. 12; kernels/material/fixed_corotated.h)
// for F [9, n] planes, with μ, λ from Young's modulus E and Poisson's ratio ν (0-d tensors) as in
// material::lame_from_young_poisson. J F⁻ᵀ is the cofactor matrix, a polynomial in F, so P is finite
// for every finite F.
torch::Tensor fixed_corotated_stress(const torch::Tensor& F, const torch::Tensor& youngs, const torch::Tensor& poisson);

}  // namespace romp::nn::nclaw
