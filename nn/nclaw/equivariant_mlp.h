// EquivariantMlp: Y(F) = R · sym(MLP(invariants of F)), the shared core of the neural elastic and plastic laws.
//
// Ma et al. 2023, Alg. 4 lines 1–5 and App. C: the MLP sees only rotation invariants of F, its 3×3
// output is symmetrised, and the polar rotation R of F is multiplied back, so Y(Q F) = Q Y(F) for
// every rotation Q. As in the authors' code the MLP is 13 → 64 → 64 → 9 with GELU, no biases and
// Xavier-uniform weights: with no biases, GELU(0) = 0 and invariants that vanish at F = I, Y(I) = 0
// exactly, so an untrained law is stress-free at rest. The module holds the weights; the evaluation is
// one fused autograd function (nn/nclaw/fused_law.h), whose sizes are compile-time constants.
#pragma once

#include <torch/torch.h>

#include "kernels/nclaw/law_network.h"
#include "nn/nclaw/fused_law.h"

namespace romp::nn::nclaw {

inline constexpr int64_t kLawInputs = romp::nclaw::kLawInputs;    // σ − 1 (3), FᵀF − I (9), det F − 1 (1)
inline constexpr int64_t kLawWidth = romp::nclaw::kLawWidth;      // hidden width of both laws (App. D.2)
inline constexpr int64_t kLawOutputs = romp::nclaw::kLawOutputs;  // a 3×3 matrix, symmetrised

class EquivariantMlpImpl : public torch::nn::Module {
 public:
  EquivariantMlpImpl();

  // scale · Y [9, n] from F [9, n] (engine planes), plus F when adds_input.
  torch::Tensor forward(const torch::Tensor& F, double scale = 1.0, bool adds_input = false);

  // The weight matrices [outputs, inputs], as torch::nn::Linear holds them.
  const LawParameters& weights() const { return weights_; }

 private:
  LawParameters weights_;
};
TORCH_MODULE(EquivariantMlp);

}  // namespace romp::nn::nclaw
