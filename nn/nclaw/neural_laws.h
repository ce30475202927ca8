// The neural elastic and plastic constitutive laws of Ma et al. 2023 (Alg. 4), as LibTorch modules on engine planes.
#pragma once

#include <torch/torch.h>

#include <vector>

#include "nn/diffmpm/rollout.h"
#include "nn/nclaw/equivariant_mlp.h"

namespace romp::nn::nclaw {

// α of the plastic law F_new = F + α R T (App. C.1: "α = 0.001 in all our experiments").
inline constexpr double kPlasticStep = 1e-3;

// Elastic law: the first Piola–Kirchhoff stress P = R T(F) [9, n] of the elastic F [9, n].
class ElasticLawImpl : public torch::nn::Module {
 public:
  ElasticLawImpl();
  torch::Tensor forward(const torch::Tensor& F);
  const LawParameters& weights() const { return core_->weights(); }

 private:
  EquivariantMlp core_;
};
TORCH_MODULE(ElasticLaw);

// Plastic law: the projected elastic F_new = F + α R T(F) [9, n] of a trial F [9, n].
class PlasticLawImpl : public torch::nn::Module {
 public:
  explicit PlasticLawImpl(double step = kPlasticStep);
  torch::Tensor forward(const torch::Tensor& F);
  double step() const { return step_; }
  const LawParameters& weights() const { return core_->weights(); }

 private:
  EquivariantMlp core_;
  double step_;
};
TORCH_MODULE(PlasticLaw);

// The pair a material learns: both networks, moved and used together.
struct NeuralLaws {
  ElasticLaw elastic;
  PlasticLaw plastic;

  // The laws of a rollout; they refer to these modules, which must outlive the rollout's backward pass.
  diffmpm::ConstitutiveLaws constitutive() const;
  // Every weight of both networks, elastic first.
  std::vector<torch::Tensor> parameters() const;
  void to(const torch::Device& device, torch::ScalarType dtype);
};

// Both laws with Xavier-uniform weights drawn after torch::manual_seed(seed), in `options`' dtype
// and on its device: the same seed gives the same laws.
NeuralLaws seeded_laws(uint64_t seed, const torch::TensorOptions& options);

}  // namespace romp::nn::nclaw
