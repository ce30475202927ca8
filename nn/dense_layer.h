// dense(X, W) = X Wᵀ as a LibTorch autograd function on romp's dense-layer kernels (kernels/mlp).
#pragma once

#include <torch/torch.h>

namespace romp::nn {

// X [rows, inputs] and W [outputs, inputs], float32 or float64, on one device: X Wᵀ [rows, outputs],
// differentiable in X and W. Throws romp::Error naming the argument whose shape, dtype or device is wrong.
torch::Tensor dense(const torch::Tensor& X, const torch::Tensor& W);

}  // namespace romp::nn
