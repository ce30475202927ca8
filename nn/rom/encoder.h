// The encoder e of the ROM paper (Sec. 4.1, Table 1): the deformed positions of Q material points of a snapshot
// → its generalized coordinates x̂, through strided 1D convolutions and two affine layers.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <vector>

#include "nn/rom/encoder_shape.h"

namespace romp::nn::rom {

class EncoderImpl : public torch::nn::Module {
 public:
  // Deformed positions are normalised with the deformation map's reference bounding box X_min .. X_max ([3]).
  // Xavier-uniform weights, zero biases, from torch's global generator.
  EncoderImpl(std::int64_t points, std::int64_t latent, const torch::Tensor& X_min, const torch::Tensor& X_max);

  // x̂ of B snapshots from the positions x [B, Q, 3] of their encoder points (in a fixed order) → [B, r].
  torch::Tensor forward(const torch::Tensor& x) const;

  std::int64_t points() const { return points_; }
  std::int64_t latent() const { return latent_; }
  // Flattened length after the convolutions (the first affine layer's input).
  std::int64_t conv_features() const;
  const std::vector<torch::nn::Conv1d>& convolutions() const { return convolutions_; }
  // The two affine layers; an ELU follows the first.
  const std::vector<torch::nn::Linear>& linears() const { return linears_; }

 private:
  std::int64_t points_, latent_;
  std::vector<torch::nn::Conv1d> convolutions_;
  std::vector<torch::nn::Linear> linears_;
  torch::Tensor X_min_, X_max_;  // buffers
};
TORCH_MODULE(Encoder);

}  // namespace romp::nn::rom
