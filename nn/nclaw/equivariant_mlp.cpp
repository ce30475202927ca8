// EquivariantMlp: invariant features → bias-free GELU MLP → symmetric T → R T.
#include "nn/nclaw/equivariant_mlp.h"

#include "nn/dense_layer.h"
#include "nn/nclaw/features.h"

namespace romp::nn {

EquivariantMlpImpl::EquivariantMlpImpl(int64_t width) {
  const auto xavier = [&](const char* name, int64_t outputs, int64_t inputs) {
    torch::Tensor weight = register_parameter(name, torch::empty({outputs, inputs}));
    torch::nn::init::xavier_uniform_(weight);
    return weight;
  };
  input_weight_ = xavier("input_weight", width, kLawInputs);
  hidden_weight_ = xavier("hidden_weight", width, width);
  output_weight_ = xavier("output_weight", kLawOutputs, width);
}

torch::Tensor EquivariantMlpImpl::forward(const torch::Tensor& F) {
  const StretchRotation polar = stretch_and_rotation(F);
  const torch::Tensor features = invariant_features(planes_to_matrices(F), polar.sigma);
  const torch::Tensor hidden = torch::gelu(dense(torch::gelu(dense(features, input_weight_)), hidden_weight_));
  const torch::Tensor T = dense(hidden, output_weight_).reshape({-1, 3, 3});
  return matrices_to_planes(torch::bmm(polar.R, 0.5 * (T + T.transpose(1, 2))));
}

}  // namespace romp::nn
