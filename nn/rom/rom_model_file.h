// The ROM model file (HDF5): everything the online stage needs to evaluate g and its derivatives straight from
// the weights (LibTorch or a fused kernel), the encoder, and how the model was trained. No LibTorch serialisation.
//
// Layout and reading rules: rom_model_file_content.h.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <string>

#include "nn/io/hdf5_file.h"
#include "nn/rom/rom_model.h"
#include "nn/rom/rom_model_file_content.h"

namespace romp::nn::rom {

// Written to "<path>.partial" and renamed to `path` once complete, so a model file is never half written.
void write_rom_model(const std::string& path, const RomModel& model);
// The model on `device`, every weight float32. Throws io::UnusableFileError naming the file and
// the object when it is not a valid model.
RomModel read_rom_model(const std::string& path, const torch::Device& device = torch::kCPU);

// The groups below the root attributes format and format_version, into or from `root` (a checkpoint keeps a
// model under /model).
void write_model_groups(io::hdf5::Group& root, const RomModel& model);
RomModel read_model_groups(const io::hdf5::Group& root, const torch::Device& device);

// A float32 copy of `tensor` as a dataset of its shape, and back (checked for shape and finite values).
void write_tensor(io::hdf5::Group& group, const std::string& path, const torch::Tensor& tensor);
torch::Tensor read_tensor(const io::hdf5::Group& group, const std::string& path,
                          const std::vector<std::int64_t>& shape);

}  // namespace romp::nn::rom
