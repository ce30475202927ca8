// The encoder's fixed sizes (Table 1 of the ROM paper) and the layer count and lengths they give for Q points, as
// plain numbers (no LibTorch): the model file's reader checks a stored encoder against them.
#pragma once

#include <cstdint>

namespace romp::nn::rom {

// Table 1: Conv1d layers with kernel 6 and stride 2 over the point sequence, 3 channels (x, y, z), until the
// flattened length d_conv is as low as possible but no smaller than 32; then affine d_conv → 32 → r.
inline constexpr std::int64_t kEncoderChannels = 3;
inline constexpr std::int64_t kEncoderKernel = 6;
inline constexpr std::int64_t kEncoderStride = 2;
inline constexpr std::int64_t kEncoderHidden = 32;

// The number of convolutions Table 1's rule applies to a sequence of `points` positions.
std::int64_t encoder_conv_layers(std::int64_t points);
// d_conv: the flattened length after those convolutions (the first affine layer's input).
std::int64_t encoder_conv_features(std::int64_t points);

}  // namespace romp::nn::rom
