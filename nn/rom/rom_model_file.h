// The ROM model file (HDF5): everything the online stage needs to evaluate g and its derivatives straight from
// the weights (LibTorch or a fused kernel), the encoder, and how the model was trained. No LibTorch serialisation.
//
// Layout (format "romp-rom-model", format_version 1; every array f32 unless marked, shapes row-major):
//   /                    attributes format, format_version, romp_version, commit, latent (r)
//   /normalisation       X_min [3], X_max [3]: network input X̄ = (X − X_min) / (X_max − X_min);
//                        u_mean [3], u_std [3]: x = X + u_mean + u_std ⊙ out
//   /map                 attributes kind ("mlp", or "linear" for the baseline of Sec. 5.4.1), activation ("elu",
//                        α = 1), hidden_layers (H), width, input ("[xhat, Xbar]", r + 3 values), output
//                        ("standardised displacement", 3 values)
//   /map/layer_K         weight [out, in], bias [out] for K = 0 .. H: out = weight · in + bias; ELU after every
//                        layer but the last; layer_0 has in = r + 3 (x̂ first), layer_H has out = 3
//   /encoder             attributes kind ("conv1d"), activation ("elu"), points (Q), particle_count (P of the
//                        training snapshots), conv_layers, kernel (6), stride (2), channels (3), hidden (32)
//   /encoder/indices     [Q] i64, increasing: the material points (initial order) whose deformed positions,
//                        normalised like X, form the input [3 channels, Q]
//   /encoder/conv_K      weight [3, 3, 6], bias [3], K = 0 .. conv_layers − 1, each followed by ELU
//   /encoder/linear_0    weight [32, 3·L], bias [32] (L: sequence length after the convolutions), then ELU
//   /encoder/linear_1    weight [r, 32], bias [r]
//   /training            attributes sweep_dir, parameter_names, epochs, epochs_done, batch, points,
//                        encoder_points, seed (i64), lambda_F, lambda_v, learning_rate, decay_at (f64 list),
//                        derivatives ("analytic" | "autograd"), {train,test}_{position,F,velocity}_error
//                        (relative L2, NaN where not measured)
//   /training/members    index [M] i64, test [M] i32 (1: held out), values [M, p] f64 (μ per parameter_names);
//                        attribute snapshots (file names in the sweep folder)
// Reading checks every attribute and shape against these rules and that every weight is finite; errors name
// the file and the object ("model m.h5: dataset /map/layer_2/weight: shape [30, 31], expected [30, 30]").
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <string>

#include "nn/io/hdf5_file.h"
#include "nn/io/versioned_file.h"
#include "nn/rom/rom_model.h"

namespace romp::nn::rom {

inline constexpr io::FileFormat kRomModelFileFormat{"model", "romp-rom-model", "a romp ROM model", 1};

// Written to "<path>.partial" and renamed to `path` once complete, so a model file is never half written.
void write_rom_model(const std::string& path, const RomModel& model);
// The model on `device`, every weight float32. Throws romp::Error naming the file when it is not a valid model.
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
