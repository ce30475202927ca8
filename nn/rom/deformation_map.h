// The manifold parameterisation g(X, x̂) → x of the ROM paper (Sec. 4, Table 1): an MLP on [x̂, X normalised
// over the reference bounding box] whose output is a standardised displacement; with no hidden layer it is the
// linear-manifold baseline of Sec. 5.4.1.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <string>
#include <vector>

#include "nn/rom/map_layout.h"

namespace romp::nn::rom {

// The fixed affine maps around the network, from the training data: in, X̄ = (X − X_min) / (X_max − X_min)
// (min–max over the reference bounding box); out, u = u_mean + u_std ⊙ out, and x = X + u.
struct MapNormalisation {
  torch::Tensor X_min, X_max;   // [3]
  torch::Tensor u_mean, u_std;  // [3], u_std > 0
};

class DeformationMapImpl : public torch::nn::Module {
 public:
  // Xavier-uniform weights, zero biases, drawn from torch's global generator (seed it for reproducibility).
  DeformationMapImpl(const MapArchitecture& architecture, const MapNormalisation& normalisation);

  // x = g(X, x̂) for N points: xhat [N, r], X [N, 3] → [N, 3], in the parameters' dtype and device.
  torch::Tensor forward(const torch::Tensor& xhat, const torch::Tensor& X) const;

  // The network's input [x̂, X̄], [N, r + 3].
  torch::Tensor network_input(const torch::Tensor& xhat, const torch::Tensor& X) const;
  // x from X and the network's (standardised) output.
  torch::Tensor position(const torch::Tensor& X, const torch::Tensor& output) const;

  const MapArchitecture& architecture() const { return architecture_; }
  bool is_linear() const { return architecture_.hidden_layers == 0; }
  // The affine layers in evaluation order; an ELU follows each one except the last.
  const std::vector<torch::nn::Linear>& layers() const { return layers_; }
  MapNormalisation normalisation() const { return {X_min_, X_max_, u_mean_, u_std_}; }
  // X_max − X_min, [3].
  torch::Tensor X_extent() const { return X_max_ - X_min_; }
  const torch::Tensor& u_std() const { return u_std_; }

 private:
  MapArchitecture architecture_;
  std::vector<torch::nn::Linear> layers_;
  torch::Tensor X_min_, X_max_, u_mean_, u_std_;  // buffers: they follow the module's device and dtype
};
TORCH_MODULE(DeformationMap);

// What is wrong with a normalisation ("u_std must be positive"), or "" when it holds four finite [3] tensors with
// X_max > X_min and u_std > 0.
std::string normalisation_problem(const MapNormalisation& normalisation);
// The tensors as values, and back (float32 on the CPU); `values` requires four [3] tensors.
MapNormalisationValues normalisation_values(const MapNormalisation& normalisation);
MapNormalisation normalisation_tensors(const MapNormalisationValues& values);

}  // namespace romp::nn::rom
