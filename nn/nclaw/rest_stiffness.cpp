// Rest stiffness of an elastic law by central differences of three uniaxial stretches.
#include "nn/nclaw/rest_stiffness.h"

namespace romp::nn::nclaw {

RestStiffness rest_stiffness(const std::function<torch::Tensor(const torch::Tensor&)>& elastic,
                             torch::ScalarType dtype) {
  constexpr double kStrain = 1e-4;
  // Column 2a is I + ε e_a e_aᵀ, column 2a + 1 is I − ε e_a e_aᵀ; planes: entry (r, c) is row 3 r + c.
  torch::Tensor F = torch::zeros({9, 6}, torch::TensorOptions().dtype(dtype));
  for (int64_t column = 0; column < 6; ++column) {
    for (int64_t a = 0; a < 3; ++a) F[4 * a][column] = 1.0;
    const int64_t axis = column / 2;
    F[4 * axis][column] = 1.0 + (column % 2 == 0 ? kStrain : -kStrain);
  }
  torch::NoGradGuard no_grad;
  const torch::Tensor P = elastic(F).to(torch::kCPU, torch::kFloat64);
  double p_wave = 0.0, lambda = 0.0;
  for (int64_t axis = 0; axis < 3; ++axis) {
    for (int64_t b = 0; b < 3; ++b) {
      const double slope =
          (P[4 * b][2 * axis].item<double>() - P[4 * b][2 * axis + 1].item<double>()) / (2.0 * kStrain);
      if (b == axis)
        p_wave += slope / 3.0;
      else
        lambda += slope / 6.0;
    }
  }
  return {0.5 * (p_wave - lambda), lambda};
}

}  // namespace romp::nn::nclaw
