// EquivariantMlp: Xavier-uniform weights, evaluated by the fused law.
#include "nn/nclaw/equivariant_mlp.h"

namespace romp::nn::nclaw {

EquivariantMlpImpl::EquivariantMlpImpl() {
  const auto xavier = [&](const char* name, int64_t outputs, int64_t inputs) {
    torch::Tensor weight = register_parameter(name, torch::empty({outputs, inputs}));
    torch::nn::init::xavier_uniform_(weight);
    return weight;
  };
  weights_.input = xavier("input_weight", kLawWidth, kLawInputs);
  weights_.hidden = xavier("hidden_weight", kLawWidth, kLawWidth);
  weights_.output = xavier("output_weight", kLawOutputs, kLawWidth);
}

torch::Tensor EquivariantMlpImpl::forward(const torch::Tensor& F, double scale, bool adds_input) {
  return fused_law(F, weights_, scale, adds_input);
}

}  // namespace romp::nn::nclaw
