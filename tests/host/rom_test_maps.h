// Deformation maps for ROM tests whose motion the full-order engine reproduces exactly.
#pragma once

#include <cstddef>

#include "kernels/rom/deformation_map_eval.h"

namespace romp::test {

// x = X + out, out = [I₃ | 0] [x̂, X̄]: the translation family g(X; x̂) = X + x̂ (r = 3) as a
// one-layer (linear) map.
inline rom::DeformationMapWeights translation_map() {
  rom::DeformationMapWeights map;
  map.latent = 3;
  map.hidden_layers = 0;
  map.parameters.assign(std::size_t(rom::deformation_map_parameter_count(3, 0, 0)), 0.0f);
  for (int row = 0; row < 3; ++row) map.parameters[std::size_t(row * 6 + row)] = 1.0f;  // weight [3 × 6], bias [3]
  map.X_scale = Vec3<float>::constant(1.0f);
  map.u_std = Vec3<float>::constant(1.0f);
  return map;
}

}  // namespace romp::test
