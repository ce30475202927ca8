// The ROM model file: a model's networks to the file's content and back (rom_model_file_content.h reads and
// writes the layout and checks its rules).
#include "nn/rom/rom_model_file.h"

#include "nn/rom/rom_model_file_content.h"

namespace romp::nn::rom {
namespace {

std::vector<float> float_values(const torch::Tensor& tensor) {
  const torch::Tensor values = tensor.detach().to(torch::kCPU, torch::kFloat32).contiguous();
  return std::vector<float>(values.data_ptr<float>(), values.data_ptr<float>() + values.numel());
}

StoredLayer stored(const torch::Tensor& weight, const torch::Tensor& bias) {
  return {weight.sizes().vec(), float_values(weight), float_values(bias)};
}

// Copies a stored layer into a module's weight and bias, which have the shapes the content was checked against.
void load(const StoredLayer& layer, const torch::Tensor& weight, const torch::Tensor& bias) {
  torch::NoGradGuard no_grad;
  weight.copy_(torch::from_blob(const_cast<float*>(layer.weight.data()), layer.weight_shape, torch::kFloat32));
  bias.copy_(torch::from_blob(const_cast<float*>(layer.bias.data()), {bias.numel()}, torch::kFloat32));
}

RomModelFileContent content_of(const RomModel& model) {
  RomModelFileContent content;
  content.architecture = model.map->architecture();
  content.normalisation = normalisation_values(model.map->normalisation());
  for (const torch::nn::Linear& layer : model.map->layers())
    content.map_layers.push_back(stored(layer->weight, layer->bias));
  const torch::Tensor indices = model.encoder_indices.to(torch::kCPU, torch::kInt64).contiguous();
  content.encoder_indices.assign(indices.data_ptr<std::int64_t>(), indices.data_ptr<std::int64_t>() + indices.numel());
  for (const torch::nn::Conv1d& conv : model.encoder->convolutions())
    content.encoder_convolutions.push_back(stored(conv->weight, conv->bias));
  for (std::size_t k = 0; k < content.encoder_linears.size(); ++k)
    content.encoder_linears[k] = stored(model.encoder->linears()[k]->weight, model.encoder->linears()[k]->bias);
  content.training = model.training;
  return content;
}

RomModel model_from(const RomModelFileContent& content, const torch::Device& device) {
  RomModel model;
  const MapNormalisation normalisation = normalisation_tensors(content.normalisation);
  model.map = DeformationMap(content.architecture, normalisation);
  for (std::size_t k = 0; k < content.map_layers.size(); ++k)
    load(content.map_layers[k], model.map->layers()[k]->weight, model.map->layers()[k]->bias);
  model.encoder_indices = torch::tensor(content.encoder_indices, torch::kInt64);
  model.encoder = Encoder(std::int64_t(content.encoder_indices.size()), content.architecture.latent,
                          normalisation.X_min, normalisation.X_max);
  for (std::size_t k = 0; k < content.encoder_convolutions.size(); ++k) {
    load(content.encoder_convolutions[k], model.encoder->convolutions()[k]->weight,
         model.encoder->convolutions()[k]->bias);
  }
  for (std::size_t k = 0; k < content.encoder_linears.size(); ++k)
    load(content.encoder_linears[k], model.encoder->linears()[k]->weight, model.encoder->linears()[k]->bias);
  model.training = content.training;
  model.to(device);
  return model;
}

}  // namespace

void write_tensor(io::hdf5::Group& group, const std::string& path, const torch::Tensor& tensor) {
  const std::vector<float> values = float_values(tensor);
  group.write_dataset(path, io::hdf5::Shape(tensor.sizes().begin(), tensor.sizes().end()), values);
}

torch::Tensor read_tensor(const io::hdf5::Group& group, const std::string& path,
                          const std::vector<std::int64_t>& shape) {
  std::vector<float> values = read_finite_floats(group, path, shape);
  return torch::from_blob(values.data(), shape, torch::kFloat32).clone();
}

void write_model_groups(io::hdf5::Group& root, const RomModel& model) { write_model_content(root, content_of(model)); }

RomModel read_model_groups(const io::hdf5::Group& root, const torch::Device& device) {
  return model_from(read_model_content(root), device);
}

void write_rom_model(const std::string& path, const RomModel& model) {
  io::write_versioned_file(path, kRomModelFileFormat, [&](io::hdf5::File& file) { write_model_groups(file, model); });
}

RomModel read_rom_model(const std::string& path, const torch::Device& device) {
  return model_from(read_rom_model_file_content(path), device);
}

}  // namespace romp::nn::rom
