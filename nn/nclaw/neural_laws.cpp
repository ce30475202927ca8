// ElasticLaw and PlasticLaw: Alg. 4 lines 6–10 on top of EquivariantMlp.
#include "nn/nclaw/neural_laws.h"

namespace romp::nn::nclaw {

ElasticLawImpl::ElasticLawImpl() { register_module("core", core_); }

torch::Tensor ElasticLawImpl::forward(const torch::Tensor& F) { return core_->forward(F); }

PlasticLawImpl::PlasticLawImpl(double step) : step_(step) { register_module("core", core_); }

torch::Tensor PlasticLawImpl::forward(const torch::Tensor& F) { return core_->forward(F, step_, /*adds_input=*/true); }

diffmpm::ConstitutiveLaws NeuralLaws::constitutive() const {
  // The closures share the modules, so they see later weight updates.
  const std::shared_ptr<ElasticLawImpl> elastic_law = elastic.ptr();
  const std::shared_ptr<PlasticLawImpl> plastic_law = plastic.ptr();
  return {[elastic_law](const torch::Tensor& F) { return elastic_law->forward(F); },
          [plastic_law](const torch::Tensor& F) { return plastic_law->forward(F); }, parameters()};
}

std::vector<torch::Tensor> NeuralLaws::parameters() const {
  std::vector<torch::Tensor> all = elastic->parameters();
  for (const torch::Tensor& p : plastic->parameters()) all.push_back(p);
  return all;
}

void NeuralLaws::to(const torch::Device& device, torch::ScalarType dtype) {
  elastic->to(device, dtype);
  plastic->to(device, dtype);
}

NeuralLaws seeded_laws(uint64_t seed, const torch::TensorOptions& options) {
  torch::manual_seed(seed);
  NeuralLaws laws{ElasticLaw(), PlasticLaw()};
  laws.to(options.device(), c10::typeMetaToScalarType(options.dtype()));
  return laws;
}

}  // namespace romp::nn::nclaw
