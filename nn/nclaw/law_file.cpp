// write_law_file and read_law_file through romp::hdf5.
#include "nn/nclaw/law_file.h"

#include <cmath>

#include "kernels/core/error.h"
#include "nn/io/versioned_file.h"

namespace romp::nn::nclaw {
namespace {

// A law file whose content is not a usable law: an invalid input (exit 3), like a damaged HDF5 file.
void require(bool usable, const std::string& problem) {
  if (!usable) throw io::UnusableFileError(problem);
}

constexpr const char* kActivation = "gelu";

void write_network(io::hdf5::File& file, const std::string& group, const torch::nn::Module& network) {
  const std::vector<torch::Tensor> weights = network.parameters();
  for (size_t layer = 0; layer < weights.size(); ++layer) {
    const torch::Tensor w = weights[layer].detach().to(torch::kCPU, torch::kFloat64).contiguous();
    file.write_dataset(group + "/weight_" + std::to_string(layer), {uint64_t(w.size(0)), uint64_t(w.size(1))},
                       w.data_ptr<double>());
  }
}

void read_network(const io::hdf5::File& file, const std::string& group, torch::nn::Module& network) {
  torch::NoGradGuard no_grad;
  for (size_t layer = 0; layer < network.parameters().size(); ++layer) {
    torch::Tensor weight = network.parameters()[layer];
    const std::string name = group + "/weight_" + std::to_string(layer);
    std::vector<double> values = file.read_dataset<double>(name, {uint64_t(weight.size(0)), uint64_t(weight.size(1))});
    for (double value : values)
      require(std::isfinite(value), file.label() + ": dataset /" + name + ": holds a non-finite weight");
    weight.copy_(torch::from_blob(values.data(), weight.sizes(), torch::kFloat64));
  }
}

}  // namespace

void write_law_file(const std::string& path, const NeuralLaws& laws, const LawTrainingRecord& training) {
  io::write_versioned_file(path, kLawFile, [&](io::hdf5::File& file) {
    file.write_attribute("inputs", kLawInputs);
    file.write_attribute("width", laws.elastic->parameters().front().size(0));
    file.write_attribute("outputs", kLawOutputs);
    file.write_attribute("activation", kActivation);
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
  const io::hdf5::File file = io::open_versioned_file(path, kLawFile);
  const std::string& label = file.label();
  const int64_t inputs = file.read_int64_attribute("inputs"), outputs = file.read_int64_attribute("outputs");
  require(inputs == kLawInputs && outputs == kLawOutputs,
          label + ": attributes inputs, outputs are " + std::to_string(inputs) + ", " + std::to_string(outputs) +
              "; the laws have " + std::to_string(kLawInputs) + " inputs and " + std::to_string(kLawOutputs) +
              " outputs");
  const std::string activation = file.read_string_attribute("activation");
  require(activation == kActivation,
          label + ": attribute activation is '" + activation + "', expected '" + kActivation + "'");
  const int64_t width = file.read_int64_attribute("width");
  // The fused law kernels have the paper's sizes built in (kernels/nclaw/law_network.h).
  require(width == kLawWidth, label + ": attribute width is " + std::to_string(width) + ", allowed only " +
                                  std::to_string(kLawWidth) + " (the paper's, which romp's law kernels are built for)");
  const double step = file.read_double_attribute("plastic_step");
  require(std::isfinite(step) && step > 0.0,
          label + ": attribute plastic_step is " + std::to_string(step) + ", expected a positive number");

  LawFile law{{ElasticLaw(), PlasticLaw(step)}, {}};
  read_network(file, "elastic", *law.laws.elastic);
  read_network(file, "plastic", *law.laws.plastic);
  const io::hdf5::Group record = file.open_group("training");
  law.training.trajectory = record.read_string_attribute("trajectory");
  law.training.steps = record.read_int64_attribute("steps");
  law.training.reconstruction_error = record.read_double_attribute("reconstruction_error");
  law.training.loss = record.read_dataset<double>("loss", record.dataset_shape("loss"));
  return law;
}

}  // namespace romp::nn::nclaw
