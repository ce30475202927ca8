// Neural-law files: a learned elastic + plastic pair in HDF5 (weights, architecture, training record),
// readable without LibTorch's serialisation.
//
// Layout (format "romp-neural-law", version 1):
//   root attributes  format, format_version, inputs (13), width, outputs (9), activation ("gelu"),
//                    plastic_step (α)
//   /elastic/weight_0 [width, 13], weight_1 [width, width], weight_2 [9, width]   (f64, row-major,
//   /plastic/weight_0 ...                                                          y = W x as torch)
//   /training/loss [epochs] f64, attributes trajectory (path), steps (substeps per rollout),
//                    reconstruction_error (position_error of the final laws, m²)
#pragma once

#include <string>
#include <vector>

#include "nn/nclaw/law_file_content.h"
#include "nn/nclaw/neural_laws.h"

namespace romp::nn::nclaw {

struct LawFile {
  NeuralLaws laws;  // float32 on the CPU
  LawTrainingRecord training;
};

// Writes `path` through a temporary name, so an existing file is replaced only by a complete one.
void write_law_file(const std::string& path, const NeuralLaws& laws, const LawTrainingRecord& training);

// The file's networks as read_law_file_content reads and checks them (its errors: io::UnusableFileError
// naming the file, the object and the allowed values).
LawFile read_law_file(const std::string& path);

}  // namespace romp::nn::nclaw
