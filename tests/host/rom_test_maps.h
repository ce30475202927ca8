// Deformation maps for ROM tests whose motion the full-order engine reproduces exactly.
#pragma once

#include <cmath>
#include <cstddef>

#include "kernels/math/mat3.h"
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

// The translation family on a fixed affine deformation about `center`: g(X; x̂) = X + E (X − center) + x̂
// (r = 3), F = I + E everywhere, a one-layer (linear) map.
inline rom::DeformationMapWeights strained_translation_map(const Mat3<float>& E,
                                                           const Vec3<float>& center = Vec3<float>::zero()) {
  rom::DeformationMapWeights map = translation_map();
  const Vec3<float> shift = E * center;
  for (int row = 0; row < 3; ++row) {
    for (int c = 0; c < 3; ++c) map.parameters[std::size_t(row * 6 + 3 + c)] = E(row, c);
    map.parameters[std::size_t(18 + row)] = -shift[row];  // the bias, after the 3 × 6 weight
  }
  return map;
}

// A small nonlinear map (r = 3, one ELU layer of 8) over the box [low, low + size]³: a translation by
// x̂ (three units kept on ELU's linear side by a bias of 10) plus `amplitude` times five units with
// fixed pseudo-random weights on [x̂, X̄], which deform the body nonuniformly and depending on x̂, so
// stresses and the quadrature's choice of points matter.
inline rom::DeformationMapWeights small_nonlinear_map(float low, float size, float amplitude) {
  constexpr int kInputs = 6, kWidth = 8;
  rom::DeformationMapWeights map;
  map.latent = 3;
  map.hidden_layers = 1;
  map.width = kWidth;
  map.parameters.assign(std::size_t(rom::deformation_map_parameter_count(3, 1, kWidth)), 0.0f);
  float* hidden_weight = map.parameters.data();           // [8 × 6]
  float* hidden_bias = hidden_weight + kWidth * kInputs;  // [8]
  float* output_weight = hidden_bias + kWidth;            // [3 × 8]
  float* output_bias = output_weight + 3 * kWidth;        // [3]
  for (int o = 0; o < 3; ++o) {
    hidden_weight[o * kInputs + o] = 1.0f;
    hidden_bias[o] = 10.0f;
    output_weight[o * kWidth + o] = 1.0f;
    output_bias[o] = -10.0f;
  }
  for (int unit = 3; unit < kWidth; ++unit) {
    for (int i = 0; i < kInputs; ++i)
      hidden_weight[unit * kInputs + i] = 2.0f * std::sin(1.7f * float(unit * kInputs + i) + 0.3f);
    hidden_bias[unit] = std::cos(2.3f * float(unit));
    for (int o = 0; o < 3; ++o)
      output_weight[o * kWidth + unit] = amplitude * std::sin(0.9f * float(o * kWidth + unit));
  }
  map.X_min = Vec3<float>::constant(low);
  map.X_scale = Vec3<float>::constant(1.0f / size);
  map.u_std = Vec3<float>::constant(1.0f);
  return map;
}

}  // namespace romp::test
