// RomModel: encoding snapshots, the parameter list and initialisation.
#include "nn/rom/rom_model.h"

#include <cmath>

#include "kernels/core/error.h"

namespace romp::nn::rom {

torch::Tensor RomModel::encode(const torch::Tensor& x) const {
  ROMP_CHECK(x.dim() == 3 && x.size(2) == 3, "encode: positions must be [B, P, 3]");
  return encoder->forward(x.index_select(1, encoder_indices));
}

std::vector<torch::Tensor> RomModel::parameters() const {
  std::vector<torch::Tensor> all = map->parameters();
  for (const torch::Tensor& p : encoder->parameters()) all.push_back(p);
  return all;
}

void RomModel::to(const torch::Device& device) {
  map->to(device);
  encoder->to(device);
  encoder_indices = encoder_indices.to(device);
}

RomModel initial_model(const RomDataset& data, const TrainingSettings& settings) {
  torch::manual_seed(settings.seed);
  const MapNormalisation normalisation = data.normalisation();
  RomModel model;
  model.map = DeformationMap(settings.architecture, normalisation);
  model.encoder =
      Encoder(data.encoder_indices.size(0), settings.architecture.latent, normalisation.X_min, normalisation.X_max);
  model.encoder_indices = data.encoder_indices.to(torch::kCPU);
  model.training.sweep_dir = data.dir;
  model.training.parameter_names = data.parameter_names;
  model.training.members = data.members;
  model.training.particle_count = data.particle_count();
  model.training.settings = settings;
  model.to(data.X.device());
  return model;
}

}  // namespace romp::nn::rom
