// The neural law Y(F) = R sym(MLP(features(F))) as one LibTorch autograd function on romp's fused kernels.
//
// Forward and backward are each one launch per particle batch (kernels/nclaw/neural_law.h) plus the
// weight gradients' one; LibTorch keeps the weights, the optimiser and the loss. The kernels run on the
// tensors' device and PyTorch's current stream there, reading and writing the tensors in place.
#pragma once

#include <torch/torch.h>

namespace romp::nn::nclaw {

// The three weight matrices of a law's network, row-major [outputs, inputs] (as torch::nn::Linear).
struct LawParameters {
  torch::Tensor input;   // [64, 13]
  torch::Tensor hidden;  // [64, 64]
  torch::Tensor output;  // [9, 64]
};

// scale · R sym(MLP(features(F))) for F [9, n] (engine planes), plus F when adds_input (the plastic law
// F + α R T). float32 or float64, F and the weights on one device; differentiable in F and the weights.
// Throws romp::Error naming the tensor whose shape, dtype or device is wrong.
torch::Tensor fused_law(const torch::Tensor& F, const LawParameters& parameters, double scale, bool adds_input);

}  // namespace romp::nn::nclaw
