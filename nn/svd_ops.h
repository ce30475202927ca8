// torch::Tensor entry points of the batched 3x3 SVD and polar decomposition and their backward passes, without copies.
//
// Layout: n 3x3 matrices are a contiguous [9, n] tensor whose row 3 r + c holds entry (r, c) of every
// matrix (the engine's Mat3Planes); n 3-vectors are [3, n]. float32 or float64, on the CPU or a CUDA
// device. Every tensor of a call has F's dtype and device; kernels read and write the tensors'
// memory directly and run on PyTorch's current stream of that device. Violations throw romp::Error
// naming the argument.
#pragma once

#include <torch/torch.h>

namespace romp::nn {

struct Svd3Tensors {
  torch::Tensor U;  // [9, n] proper rotations
  torch::Tensor S;  // [3, n] σ₀ ≥ σ₁ ≥ |σ₂|, σ₂ < 0 where det F < 0
  torch::Tensor V;  // [9, n] proper rotations
};

struct Polar3Tensors {
  torch::Tensor R;  // [9, n] proper rotations U Vᵀ
  torch::Tensor S;  // [9, n] symmetric V Σ Vᵀ
};

// F = U diag(S) Vᵀ for each of the n matrices of F [9, n]; the results are new tensors.
Svd3Tensors svd3(const torch::Tensor& F);
// The same, written into U [9, n], S [3, n] and V [9, n], which must not overlap F.
void svd3_out(const torch::Tensor& F, const torch::Tensor& U, const torch::Tensor& S, const torch::Tensor& V);

// F = R S for each of the n matrices of F [9, n].
Polar3Tensors polar3(const torch::Tensor& F);
void polar3_out(const torch::Tensor& F, const torch::Tensor& R, const torch::Tensor& S);

// dL/dF [9, n] from the forward results U, S, V and the gradients dU [9, n], dS [3, n], dV [9, n].
// An undefined gradient (an output the loss does not use, as autograd passes it) counts as zero.
torch::Tensor svd3_backward(const torch::Tensor& U, const torch::Tensor& S, const torch::Tensor& V,
                            const torch::Tensor& dU, const torch::Tensor& dS, const torch::Tensor& dV);

// dL/dF [9, n] of the polar decomposition from F and the gradients dR, dS [9, n] (undefined = zero).
torch::Tensor polar3_backward(const torch::Tensor& F, const torch::Tensor& dR, const torch::Tensor& dS);

}  // namespace romp::nn
