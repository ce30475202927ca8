// The encoder e: layers and the forward pass.
#include "nn/rom/encoder.h"

#include <string>

#include "kernels/core/error.h"

namespace romp::nn::rom {

EncoderImpl::EncoderImpl(std::int64_t points, std::int64_t latent, const torch::Tensor& X_min,
                         const torch::Tensor& X_max)
    : points_(points), latent_(latent) {
  ROMP_CHECK(points >= 1, "encoder: needs at least one point");
  ROMP_CHECK(latent >= 1, "encoder: latent size r must be >= 1");
  const std::int64_t conv_layers = encoder_conv_layers(points);
  for (std::int64_t k = 0; k < conv_layers; ++k) {
    auto conv = register_module(
        "conv_" + std::to_string(k),
        torch::nn::Conv1d(
            torch::nn::Conv1dOptions(kEncoderChannels, kEncoderChannels, kEncoderKernel).stride(kEncoderStride)));
    torch::nn::init::xavier_uniform_(conv->weight);
    torch::nn::init::zeros_(conv->bias);
    convolutions_.push_back(conv);
  }
  const std::int64_t sizes[] = {conv_features(), kEncoderHidden, latent};
  for (int k = 0; k < 2; ++k) {
    auto linear = register_module("linear_" + std::to_string(k), torch::nn::Linear(sizes[k], sizes[k + 1]));
    torch::nn::init::xavier_uniform_(linear->weight);
    torch::nn::init::zeros_(linear->bias);
    linears_.push_back(linear);
  }
  X_min_ = register_buffer("X_min", X_min.detach().to(torch::kCPU, torch::kFloat32).clone());
  X_max_ = register_buffer("X_max", X_max.detach().to(torch::kCPU, torch::kFloat32).clone());
}

std::int64_t EncoderImpl::conv_features() const { return encoder_conv_features(points_); }

torch::Tensor EncoderImpl::forward(const torch::Tensor& x) const {
  ROMP_CHECK(x.dim() == 3 && x.size(1) == points_ && x.size(2) == 3,
             "encoder: positions must be [B, " + std::to_string(points_) + ", 3]");
  // Channels are the coordinates, the sequence runs over the points.
  torch::Tensor h = ((x - X_min_) / (X_max_ - X_min_)).transpose(1, 2);
  for (const torch::nn::Conv1d& conv : convolutions_) {
    h = torch::elu(torch::conv1d(h, conv->weight, conv->bias, kEncoderStride));
  }
  h = torch::elu(torch::linear(h.flatten(1), linears_[0]->weight, linears_[0]->bias));
  return torch::linear(h, linears_[1]->weight, linears_[1]->bias);
}

}  // namespace romp::nn::rom
