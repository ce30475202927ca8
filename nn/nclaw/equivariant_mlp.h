// EquivariantMlp: Y(F) = R · sym(MLP(invariants of F)), the shared core of the neural elastic and plastic laws.
//
// Ma et al. 2023, Alg. 4 lines 1–5 and App. C: the MLP sees only rotation invariants of F, its 3×3
// output is symmetrised, and the polar rotation R of F is multiplied back, so Y(Q F) = Q Y(F) for
// every rotation Q. As in the authors' code the MLP is 13 → 64 → 64 → 9 with GELU, no biases and
// Xavier-uniform weights: with no biases, GELU(0) = 0 and invariants that vanish at F = I, Y(I) = 0
// exactly, so an untrained law is stress-free at rest.
#pragma once

#include <torch/torch.h>

namespace romp::nn {

inline constexpr int64_t kLawInputs = 13;   // σ − 1 (3), FᵀF − I (9), det F − 1 (1)
inline constexpr int64_t kLawWidth = 64;    // hidden width of both laws (App. D.2)
inline constexpr int64_t kLawOutputs = 9;   // a 3×3 matrix, symmetrised

class EquivariantMlpImpl : public torch::nn::Module {
 public:
  explicit EquivariantMlpImpl(int64_t width = kLawWidth);

  // Y [9, n] from F [9, n] (engine planes).
  torch::Tensor forward(const torch::Tensor& F);

 private:
  // The three weight matrices [outputs, inputs], as torch::nn::Linear holds them, applied with
  // nn::dense (romp's kernels: the system BLAS may be the slow reference one).
  torch::Tensor input_weight_, hidden_weight_, output_weight_;
};
TORCH_MODULE(EquivariantMlp);

}  // namespace romp::nn
