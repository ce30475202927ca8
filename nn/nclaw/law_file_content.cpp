// read_law_file_content through romp::hdf5.
#include "nn/nclaw/law_file_content.h"

#include <cmath>

#include "kernels/core/error.h"
#include "kernels/nclaw/law_network.h"
#include "nn/io/versioned_file.h"

namespace romp::nn::nclaw {
namespace {

// A law file whose content is not a usable law: an invalid input (exit 3), like a damaged HDF5 file.
void require(bool usable, const std::string& problem) {
  if (!usable) throw io::UnusableFileError(problem);
}

LawNetworkWeights read_network(const io::hdf5::File& file, const std::string& group) {
  LawNetworkWeights weights;
  for (std::size_t layer = 0; layer < weights.size(); ++layer) {
    const std::string name = group + "/weight_" + std::to_string(layer);
    const std::array<std::uint64_t, 2> shape = law_weight_shape(layer);
    weights[layer] = file.read_dataset<double>(name, {shape[0], shape[1]});
    for (double value : weights[layer])
      require(std::isfinite(value), file.label() + ": dataset /" + name + ": holds a non-finite weight");
  }
  return weights;
}

}  // namespace

std::array<std::uint64_t, 2> law_weight_shape(std::size_t layer) {
  constexpr std::uint64_t kInputs = romp::nclaw::kLawInputs, kWidth = romp::nclaw::kLawWidth,
                          kOutputs = romp::nclaw::kLawOutputs;
  const std::array<std::uint64_t, 2> shapes[] = {{kWidth, kInputs}, {kWidth, kWidth}, {kOutputs, kWidth}};
  return shapes[layer];
}

LawFileContent read_law_file_content(const std::string& path) {
  const io::hdf5::File file = io::open_versioned_file(path, kLawFile);
  const std::string& label = file.label();
  const int64_t inputs = file.read_int64_attribute("inputs"), outputs = file.read_int64_attribute("outputs");
  require(inputs == romp::nclaw::kLawInputs && outputs == romp::nclaw::kLawOutputs,
          label + ": attributes inputs, outputs are " + std::to_string(inputs) + ", " + std::to_string(outputs) +
              "; the laws have " + std::to_string(romp::nclaw::kLawInputs) + " inputs and " +
              std::to_string(romp::nclaw::kLawOutputs) + " outputs");
  const std::string activation = file.read_string_attribute("activation");
  require(activation == kLawActivation,
          label + ": attribute activation is '" + activation + "', expected '" + kLawActivation + "'");
  const int64_t width = file.read_int64_attribute("width");
  // The fused law kernels have the paper's sizes built in (kernels/nclaw/law_network.h).
  require(width == romp::nclaw::kLawWidth, label + ": attribute width is " + std::to_string(width) + ", allowed only " +
                                               std::to_string(romp::nclaw::kLawWidth) +
                                               " (the paper's, which romp's law kernels are built for)");
  LawFileContent content;
  content.plastic_step = file.read_double_attribute("plastic_step");
  require(
      std::isfinite(content.plastic_step) && content.plastic_step > 0.0,
      label + ": attribute plastic_step is " + std::to_string(content.plastic_step) + ", expected a positive number");

  content.elastic = read_network(file, "elastic");
  content.plastic = read_network(file, "plastic");
  const io::hdf5::Group record = file.open_group("training");
  content.training.trajectory = record.read_string_attribute("trajectory");
  content.training.steps = record.read_int64_attribute("steps");
  content.training.reconstruction_error = record.read_double_attribute("reconstruction_error");
  content.training.loss = record.read_dataset<double>("loss", record.dataset_shape("loss"));
  return content;
}

}  // namespace romp::nn::nclaw
