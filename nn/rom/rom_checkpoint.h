// Training checkpoints (HDF5) for an exact `--resume`: the model with its training record, the epochs done and
// Adam's step count and moments.
//
// Layout (format "romp-rom-checkpoint", format_version 1):
//   /                      attributes format, format_version, adam_steps
//   /model                 the model file's groups (rom_model_file.h); /model/training's epochs_done says how far
//   /adam/first/NNN        f32, shaped like the model's parameter NNN (RomModel::parameters() order)
//   /adam/second/NNN
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <string>

#include "nn/rom/adam.h"
#include "nn/rom/rom_model.h"

namespace romp::nn::rom {

struct RomCheckpoint {
  RomModel model;  // its training record: the data, the settings and the epochs done
  std::int64_t adam_steps = 0;
  std::vector<torch::Tensor> first_moments, second_moments;
};

// "<model path>.checkpoint".
std::string rom_checkpoint_path(const std::string& model_path);

// Writes "<path>.partial" and renames it to `path`, so the previous checkpoint survives a crash meanwhile.
void write_rom_checkpoint(const std::string& path, const RomModel& model, const Adam& adam);
// Throws romp::Error naming the file when it is missing or not a valid checkpoint.
RomCheckpoint read_rom_checkpoint(const std::string& path, const torch::Device& device);

}  // namespace romp::nn::rom
