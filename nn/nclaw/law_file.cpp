// write_law_file and read_law_file through romp::hdf5.
#include "nn/nclaw/law_file.h"

#include <array>

#include "kernels/core/error.h"
#include "nn/io/versioned_file.h"

namespace romp::nn::nclaw {
namespace {

void write_network(io::hdf5::File& file, const std::string& group, const torch::nn::Module& network) {
  const std::vector<torch::Tensor> weights = network.parameters();
  for (size_t layer = 0; layer < weights.size(); ++layer) {
    const torch::Tensor w = weights[layer].detach().to(torch::kCPU, torch::kFloat64).contiguous();
    file.write_dataset(group + "/weight_" + std::to_string(layer), {uint64_t(w.size(0)), uint64_t(w.size(1))},
                       w.data_ptr<double>());
  }
}

// Copies one network's weights, as read_law_file_content read and checked them, into `network`.
void load_network(LawNetworkWeights weights, torch::nn::Module& network) {
  torch::NoGradGuard no_grad;
  const std::vector<torch::Tensor> parameters = network.parameters();
  ROMP_CHECK(parameters.size() == weights.size(), "a law network holds weight_0 .. weight_2");
  for (size_t layer = 0; layer < weights.size(); ++layer) {
    const std::array<uint64_t, 2> shape = law_weight_shape(layer);
    ROMP_CHECK(uint64_t(parameters[layer].size(0)) == shape[0] && uint64_t(parameters[layer].size(1)) == shape[1],
               "law_weight_shape agrees with the networks");
    parameters[layer].copy_(torch::from_blob(weights[layer].data(), parameters[layer].sizes(), torch::kFloat64));
  }
}

}  // namespace

void write_law_file(const std::string& path, const NeuralLaws& laws, const LawTrainingRecord& training) {
  io::write_versioned_file(path, kLawFile, [&](io::hdf5::File& file) {
    file.write_attribute("inputs", kLawInputs);
    file.write_attribute("width", laws.elastic->parameters().front().size(0));
    file.write_attribute("outputs", kLawOutputs);
    file.write_attribute("activation", kLawActivation);
    file.write_attribute("plastic_step", laws.plastic->step());
    write_network(file, "elastic", *laws.elastic);
    write_network(file, "plastic", *laws.plastic);
    {
      io::hdf5::Group record = file.create_group("training");
      record.write_attribute("trajectory", training.trajectory);
      record.write_attribute("steps", training.steps);
      record.write_attribute("reconstruction_error", training.reconstruction_error);
      record.write_dataset("loss", {uint64_t(training.loss.size())}, training.loss);
    }
  });
}

LawFile read_law_file(const std::string& path) {
  LawFileContent content = read_law_file_content(path);
  LawFile law{{ElasticLaw(), PlasticLaw(content.plastic_step)}, std::move(content.training)};
  load_network(std::move(content.elastic), *law.laws.elastic);
  load_network(std::move(content.plastic), *law.laws.plastic);
  return law;
}

}  // namespace romp::nn::nclaw
