// The neural law composed of LibTorch operators, as romp evaluated it before the fused kernels: the
// independent reference fused_law (nn/nclaw/fused_law.h) is tested against, and the baseline romp-bench's
// law suite times it against.
#pragma once

#include <torch/torch.h>

#include "nn/nclaw/fused_law.h"

namespace romp::nn::nclaw {

// scale · R sym(MLP(features(F))) (+ F when adds_input) for F [9, n]: features and R from the
// differentiable SVD (nn/nclaw/features.h), torch's exact GELU and matrix products; differentiable by
// LibTorch's autograd in F and the weights.
torch::Tensor composed_law(const torch::Tensor& F, const LawParameters& parameters, double scale, bool adds_input);

}  // namespace romp::nn::nclaw
