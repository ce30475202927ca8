// A neural-law file's content as plain arrays, read and checked without LibTorch (law_file.h has the layout
// and loads the weights into the networks): what the law fuzz harness reads.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "nn/nclaw/law_file_format.h"

namespace romp::nn::nclaw {

// How the laws were learned.
struct LawTrainingRecord {
  std::string trajectory;             // the ground-truth file
  int64_t steps = 0;                  // substeps per training rollout
  std::vector<double> loss;           // per epoch
  double reconstruction_error = 0.0;  // position_error of the final laws on the trajectory (m²)
};

inline constexpr const char* kLawActivation = "gelu";  // attribute activation

// One network's weight_0 .. weight_2, row-major [outputs, inputs] as torch::nn::Linear holds them.
using LawNetworkWeights = std::array<std::vector<double>, 3>;

struct LawFileContent {
  LawNetworkWeights elastic, plastic;  // every value finite
  double plastic_step = 0.0;           // α, positive
  LawTrainingRecord training;
};

// The shape [outputs, inputs] of weight_`layer` (0 .. 2) of either network.
std::array<std::uint64_t, 2> law_weight_shape(std::size_t layer);

// Throws io::UnusableFileError naming the file, the object and the allowed values when it is not a complete
// law file of this version (wrong format, architecture, shapes, or non-finite weights).
LawFileContent read_law_file_content(const std::string& path);

}  // namespace romp::nn::nclaw
