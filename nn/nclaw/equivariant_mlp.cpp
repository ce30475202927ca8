// EquivariantMlp: invariant features → bias-free GELU MLP → symmetric T → R T.
#include "nn/nclaw/equivariant_mlp.h"

#include "nn/nclaw/features.h"

namespace romp::nn {
namespace {

torch::nn::Linear bias_free_layer(int64_t inputs, int64_t outputs) {
  torch::nn::Linear layer(torch::nn::LinearOptions(inputs, outputs).bias(false));
  torch::nn::init::xavier_uniform_(layer->weight);
  return layer;
}

}  // namespace

EquivariantMlpImpl::EquivariantMlpImpl(int64_t width)
    : mlp_(bias_free_layer(kLawInputs, width), torch::nn::GELU(), bias_free_layer(width, width), torch::nn::GELU(),
           bias_free_layer(width, kLawOutputs)) {
  register_module("mlp", mlp_);
}

torch::Tensor EquivariantMlpImpl::forward(const torch::Tensor& F) {
  const StretchRotation polar = stretch_and_rotation(F);
  const torch::Tensor T = mlp_->forward(invariant_features(planes_to_matrices(F), polar.sigma)).reshape({-1, 3, 3});
  return matrices_to_planes(torch::bmm(polar.R, 0.5 * (T + T.transpose(1, 2))));
}

}  // namespace romp::nn
