// The neural-law file's format name and version (law_file.h has its layout), without LibTorch: what the
// scene parser checks of a law a scene names, without loading or evaluating its networks.
#pragma once

#include "nn/io/versioned_file.h"

namespace romp::nn::nclaw {

inline constexpr io::FileFormat kLawFile{"neural law", "romp-neural-law", "a romp neural-law file", 1};

}  // namespace romp::nn::nclaw
