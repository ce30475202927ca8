// RomModel: encoding snapshots, the parameter list, initialisation, and the settings' learning-rate stages.
#include "nn/rom/rom_model.h"

#include <cmath>
#include <sstream>

#include "kernels/core/error.h"

namespace romp::nn::rom {
namespace {

template <class T>
std::string text(const T& value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string text(const std::vector<double>& values) {
  std::string joined;
  for (double value : values) joined += (joined.empty() ? "" : ",") + text(value);
  return joined;
}

}  // namespace

double TrainingSettings::learning_rate_at(std::int64_t epoch) const {
  double rate = learning_rate;
  for (double fraction : decay_at) {
    if (double(epoch) >= fraction * double(epochs)) rate *= 0.1;
  }
  return rate;
}

std::vector<std::string> TrainingSettings::differences(const TrainingSettings& other) const {
  std::vector<std::string> found;
  const auto compare = [&](const char* name, const auto& mine, const auto& theirs) {
    if (mine != theirs)
      found.push_back(std::string(name) + ": " + text(mine) + " here, " + text(theirs) + " in the other");
  };
  compare("latent", architecture.latent, other.architecture.latent);
  compare("hidden layers", architecture.hidden_layers, other.architecture.hidden_layers);
  compare("width", architecture.width, other.architecture.width);
  compare("encoder points", encoder_points, other.encoder_points);
  compare("epochs", epochs, other.epochs);
  compare("batch", batch, other.batch);
  compare("points", points, other.points);
  compare("seed", seed, other.seed);
  compare("lambda_F", loss_weights.F, other.loss_weights.F);
  compare("lambda_v", loss_weights.velocity, other.loss_weights.velocity);
  compare("learning rate", learning_rate, other.learning_rate);
  compare("decay at", decay_at, other.decay_at);
  compare("derivatives", std::string(to_string(derivatives)), std::string(to_string(other.derivatives)));
  return found;
}

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
