// A ROM model file's content as plain arrays, read and checked without LibTorch (rom_model_file.h builds the
// networks from it and writes a model through it): what the model fuzz harness reads.
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

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "nn/io/hdf5_file.h"
#include "nn/io/versioned_file.h"
#include "nn/rom/map_layout.h"
#include "nn/rom/training_record.h"

namespace romp::nn::rom {

inline constexpr io::FileFormat kRomModelFileFormat{"model", "romp-rom-model", "a romp ROM model", 1};

// One stored affine layer or convolution: weight of `weight_shape` (row-major), bias [weight_shape[0]].
struct StoredLayer {
  std::vector<std::int64_t> weight_shape;
  std::vector<float> weight, bias;  // every value finite once read
};

struct RomModelFileContent {
  MapArchitecture architecture;  // latent ≤ the fused kernels' limit; hidden_layers 0 is the "linear" kind
  MapNormalisationValues normalisation;
  std::vector<StoredLayer> map_layers;            // layer_0 .. layer_H, shapes map_layer_shapes(architecture)
  std::vector<std::int64_t> encoder_indices;      // [Q], increasing, below training.particle_count
  std::vector<StoredLayer> encoder_convolutions;  // conv_0 .. , encoder_conv_layers(Q) of them
  std::array<StoredLayer, 2> encoder_linears;     // d_conv → 32 → r
  TrainingRecord training;                        // with particle_count, romp_version and commit
};

// The groups below the root attributes format and format_version, into or from `root` (a checkpoint keeps a
// model under /model). Reading throws io::UnusableFileError naming the file, the object and the allowed values
// when any rule of the layout fails; sizes are checked against their bounds before anything of their size is
// read, so a damaged file cannot ask for more memory than a model could need.
void write_model_content(io::hdf5::Group& root, const RomModelFileContent& content);
RomModelFileContent read_model_content(const io::hdf5::Group& root);

// A float32 dataset of `shape` whose every value is finite; io::UnusableFileError naming it otherwise.
std::vector<float> read_finite_floats(const io::hdf5::Group& group, const std::string& path,
                                      const std::vector<std::int64_t>& shape);

// A whole model file: its format and version checked, then read_model_content.
RomModelFileContent read_rom_model_file_content(const std::string& path);

}  // namespace romp::nn::rom
