// The deformation map g: layers, normalisation buffers and the forward pass.
#include "nn/rom/deformation_map.h"

#include <string>

#include "kernels/core/error.h"

namespace romp::nn::rom {

std::string normalisation_problem(const MapNormalisation& n) {
  const std::pair<const char*, const torch::Tensor*> parts[] = {
      {"X_min", &n.X_min}, {"X_max", &n.X_max}, {"u_mean", &n.u_mean}, {"u_std", &n.u_std}};
  for (const auto& [name, tensor] : parts) {
    if (!tensor->defined() || tensor->dim() != 1 || tensor->size(0) != 3)
      return std::string(name) + " must hold 3 values";
  }
  return normalisation_problem(normalisation_values(n));
}

MapNormalisationValues normalisation_values(const MapNormalisation& n) {
  const auto values = [](const torch::Tensor& tensor) {
    ROMP_CHECK(tensor.defined() && tensor.numel() == 3, "deformation map normalisation: a part must hold 3 values");
    const torch::Tensor cpu = tensor.detach().to(torch::kCPU, torch::kFloat32).contiguous();
    return std::array<float, 3>{cpu.data_ptr<float>()[0], cpu.data_ptr<float>()[1], cpu.data_ptr<float>()[2]};
  };
  return {values(n.X_min), values(n.X_max), values(n.u_mean), values(n.u_std)};
}

MapNormalisation normalisation_tensors(const MapNormalisationValues& values) {
  const auto tensor = [](const std::array<float, 3>& part) {
    return torch::tensor(std::vector<float>(part.begin(), part.end()), torch::kFloat32);
  };
  return {tensor(values.X_min), tensor(values.X_max), tensor(values.u_mean), tensor(values.u_std)};
}

DeformationMapImpl::DeformationMapImpl(const MapArchitecture& architecture, const MapNormalisation& normalisation)
    : architecture_(architecture) {
  ROMP_CHECK(architecture.latent >= 1, "deformation map: latent size r must be >= 1");
  ROMP_CHECK(architecture.hidden_layers >= 0, "deformation map: hidden layer count must be >= 0");
  ROMP_CHECK(architecture.hidden_layers == 0 || architecture.width >= 1, "deformation map: width must be >= 1");
  const std::string problem = normalisation_problem(normalisation);
  ROMP_CHECK(problem.empty(), "deformation map normalisation: " + problem);
  for (const auto& [out, in] : map_layer_shapes(architecture)) {
    torch::nn::Linear layer = register_module("layer_" + std::to_string(layers_.size()), torch::nn::Linear(in, out));
    torch::nn::init::xavier_uniform_(layer->weight);
    torch::nn::init::zeros_(layer->bias);
    layers_.push_back(layer);
  }
  const auto as_float = [](const torch::Tensor& t) { return t.detach().to(torch::kCPU, torch::kFloat32).clone(); };
  X_min_ = register_buffer("X_min", as_float(normalisation.X_min));
  X_max_ = register_buffer("X_max", as_float(normalisation.X_max));
  u_mean_ = register_buffer("u_mean", as_float(normalisation.u_mean));
  u_std_ = register_buffer("u_std", as_float(normalisation.u_std));
}

torch::Tensor DeformationMapImpl::network_input(const torch::Tensor& xhat, const torch::Tensor& X) const {
  ROMP_CHECK(xhat.dim() == 2 && xhat.size(1) == architecture_.latent,
             "deformation map: x̂ must be [N, " + std::to_string(architecture_.latent) + "]");
  ROMP_CHECK(X.dim() == 2 && X.size(1) == 3 && X.size(0) == xhat.size(0),
             "deformation map: X must be [N, 3] with as many rows as x̂");
  return torch::cat({xhat, (X - X_min_) / X_extent()}, 1);
}

torch::Tensor DeformationMapImpl::position(const torch::Tensor& X, const torch::Tensor& output) const {
  return X + u_mean_ + u_std_ * output;
}

torch::Tensor DeformationMapImpl::forward(const torch::Tensor& xhat, const torch::Tensor& X) const {
  torch::Tensor h = network_input(xhat, X);
  for (std::size_t k = 0; k < layers_.size(); ++k) {
    h = torch::linear(h, layers_[k]->weight, layers_[k]->bias);
    if (k + 1 < layers_.size()) h = torch::elu(h);
  }
  return position(X, h);
}

}  // namespace romp::nn::rom
