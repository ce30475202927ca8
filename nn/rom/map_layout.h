// The deformation map's sizes and normalisation as plain values (no LibTorch): what the model file stores and
// what its reader checks before any module is built (deformation_map.h builds the network from them).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace romp::nn::rom {

struct MapArchitecture {
  std::int64_t latent = 6;         // r, the number of generalized coordinates
  std::int64_t hidden_layers = 5;  // ELU layers of `width`; 0 is the linear baseline (one affine layer)
  std::int64_t width = 30;
};

// The authors' code: 5 hidden layers of width 30. (Table 1 lists 5 affine layers, i.e. 4 hidden ones; the
// model file records the layer list, so either reads back.)
inline constexpr std::int64_t kDefaultHiddenLayers = 5;

// The shape [outputs, inputs] of each affine layer in evaluation order: r + 3 → width → … → width → 3.
std::vector<std::array<std::int64_t, 2>> map_layer_shapes(const MapArchitecture& architecture);

// The fixed affine maps around the network as values: X̄ = (X − X_min) / (X_max − X_min) and
// x = X + u_mean + u_std ⊙ out (deformation_map.h's MapNormalisation holds them as tensors).
struct MapNormalisationValues {
  std::array<float, 3> X_min{}, X_max{}, u_mean{}, u_std{};
};

// What is wrong with a normalisation ("u_std must be positive"), or "" when every value is finite,
// X_max > X_min and u_std > 0.
std::string normalisation_problem(const MapNormalisationValues& normalisation);

}  // namespace romp::nn::rom
