// fixed_corotated_stress: Eq. 12 of Ma et al. 2023 with the rotation from the differentiable SVD.
#include "nn/nclaw/fixed_corotated.h"

#include "nn/nclaw/features.h"

namespace romp::nn::nclaw {

torch::Tensor fixed_corotated_stress(const torch::Tensor& F, const torch::Tensor& youngs,
                                     const torch::Tensor& poisson) {
  const torch::Tensor mu = youngs / (2.0 * (1.0 + poisson));
  const torch::Tensor lambda = youngs * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
  const torch::Tensor matrices = planes_to_matrices(F);
  const torch::Tensor R = stretch_and_rotation(F).R;
  // The rows of cof F are r₁ × r₂, r₂ × r₀, r₀ × r₁ for the rows rᵢ of F, and J = r₀ · (r₁ × r₂).
  const torch::Tensor r0 = matrices.select(1, 0), r1 = matrices.select(1, 1), r2 = matrices.select(1, 2);
  const torch::Tensor cofactor =
      torch::stack({torch::cross(r1, r2, 1), torch::cross(r2, r0, 1), torch::cross(r0, r1, 1)}, 1);
  const torch::Tensor J = (r0 * cofactor.select(1, 0)).sum(1).reshape({-1, 1, 1});
  return matrices_to_planes(2.0 * mu * (matrices - R) + lambda * (J - 1.0) * cofactor);
}

}  // namespace romp::nn::nclaw
