// Packing a LibTorch deformation map for the fused evaluator.
#include "nn/rom/fused_map.h"

#include <string>

#include "kernels/core/error.h"

namespace romp::nn::rom {
namespace {

Vec3<float> vec3(const torch::Tensor& t) {
  const torch::Tensor c = t.detach().to(torch::kCPU, torch::kFloat32).contiguous();
  const float* v = c.data_ptr<float>();
  return Vec3<float>(v[0], v[1], v[2]);
}

void append(std::vector<float>& values, const torch::Tensor& t) {
  const torch::Tensor c = t.detach().to(torch::kCPU, torch::kFloat32).contiguous();
  values.insert(values.end(), c.data_ptr<float>(), c.data_ptr<float>() + c.numel());
}

}  // namespace

romp::rom::DeformationMapWeights fused_weights(const DeformationMapImpl& map) {
  const MapArchitecture& a = map.architecture();
  ROMP_CHECK(a.latent >= 1 && a.latent <= romp::rom::kMaxMapLatent,
             "the fused evaluator takes r <= " + std::to_string(romp::rom::kMaxMapLatent) + ", the map has " +
                 std::to_string(a.latent));
  ROMP_CHECK(a.hidden_layers <= romp::rom::kMaxMapHiddenLayers && a.width <= romp::rom::kMaxMapWidth,
             "the fused evaluator takes up to " + std::to_string(romp::rom::kMaxMapHiddenLayers) +
                 " hidden layers of up to " + std::to_string(romp::rom::kMaxMapWidth) + " units");
  romp::rom::DeformationMapWeights weights;
  weights.latent = int(a.latent);
  weights.hidden_layers = int(a.hidden_layers);
  weights.width = int(a.width);
  // torch::nn::Linear keeps weight [out, in] row-major: the packed layout's order.
  for (const torch::nn::Linear& layer : map.layers()) {
    append(weights.parameters, layer->weight);
    append(weights.parameters, layer->bias);
  }
  const MapNormalisation n = map.normalisation();
  weights.X_min = vec3(n.X_min);
  const Vec3<float> extent = vec3(n.X_max) - weights.X_min;
  weights.X_scale = Vec3<float>(1.0f / extent[0], 1.0f / extent[1], 1.0f / extent[2]);
  weights.u_mean = vec3(n.u_mean);
  weights.u_std = vec3(n.u_std);
  return weights;
}

}  // namespace romp::nn::rom
