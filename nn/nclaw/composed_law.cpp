// composed_law: the law op by op.
#include "nn/nclaw/composed_law.h"

#include "nn/nclaw/features.h"

namespace romp::nn::nclaw {

torch::Tensor composed_law(const torch::Tensor& F, const LawParameters& w, double scale, bool adds_input) {
  const StretchRotation polar = stretch_and_rotation(F);
  const torch::Tensor features = invariant_features(planes_to_matrices(F), polar.sigma);
  const torch::Tensor hidden = torch::gelu(torch::gelu(features.matmul(w.input.t())).matmul(w.hidden.t()));
  const torch::Tensor T = hidden.matmul(w.output.t()).reshape({-1, 3, 3});
  const torch::Tensor Y = scale * matrices_to_planes(torch::bmm(polar.R, 0.5 * (T + T.transpose(1, 2))));
  return adds_input ? F + Y : Y;
}

}  // namespace romp::nn::nclaw
