// Training checkpoints: the model's groups plus Adam's state, written atomically and read back checked.
#include "nn/rom/rom_checkpoint.h"

#include <fmt/format.h>

#include "kernels/core/error.h"
#include "nn/io/versioned_file.h"
#include "nn/rom/rom_model_file.h"

namespace romp::nn::rom {
namespace {

constexpr io::FileFormat kCheckpointFileFormat{"checkpoint", "romp-rom-checkpoint", "a ROM training checkpoint", 1};

std::string moment_path(const char* which, std::size_t index) { return fmt::format("adam/{}/{:03}", which, index); }

}  // namespace

std::string rom_checkpoint_path(const std::string& model_path) { return model_path + ".checkpoint"; }

void write_rom_checkpoint(const std::string& path, const RomModel& model, const Adam& adam) {
  io::write_versioned_file(path, kCheckpointFileFormat, [&](io::hdf5::File& file) {
    file.write_attribute("adam_steps", adam.steps());
    io::hdf5::Group group = file.create_group("model");
    write_model_groups(group, model);
    for (std::size_t i = 0; i < adam.first_moments().size(); ++i) {
      write_tensor(file, moment_path("first", i), adam.first_moments()[i]);
      write_tensor(file, moment_path("second", i), adam.second_moments()[i]);
    }
  });
}

RomCheckpoint read_rom_checkpoint(const std::string& path, const torch::Device& device) {
  const io::hdf5::File file = io::open_versioned_file(path, kCheckpointFileFormat);
  RomCheckpoint checkpoint;
  checkpoint.adam_steps = file.read_int64_attribute("adam_steps");
  if (checkpoint.adam_steps < 0) throw io::UnusableFileError(file.label() + ": attribute /adam_steps is negative");
  checkpoint.model = read_model_groups(file.open_group("model"), device);
  const std::vector<torch::Tensor> parameters = checkpoint.model.parameters();
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    const std::vector<std::int64_t> shape = parameters[i].sizes().vec();
    checkpoint.first_moments.push_back(read_tensor(file, moment_path("first", i), shape).to(device));
    checkpoint.second_moments.push_back(read_tensor(file, moment_path("second", i), shape).to(device));
  }
  return checkpoint;
}

}  // namespace romp::nn::rom
