// Table 1's convolution count and the encoder's flattened length.
#include "nn/rom/encoder_shape.h"

namespace romp::nn::rom {
namespace {

std::int64_t conv_length(std::int64_t length) { return (length - kEncoderKernel) / kEncoderStride + 1; }

}  // namespace

std::int64_t encoder_conv_layers(std::int64_t points) {
  std::int64_t layers = 0;
  for (std::int64_t length = points;
       length >= kEncoderKernel && kEncoderChannels * conv_length(length) >= kEncoderHidden;
       length = conv_length(length)) {
    ++layers;
  }
  return layers;
}

std::int64_t encoder_conv_features(std::int64_t points) {
  std::int64_t length = points;
  for (std::int64_t k = encoder_conv_layers(points); k > 0; --k) length = conv_length(length);
  return kEncoderChannels * length;
}

}  // namespace romp::nn::rom
