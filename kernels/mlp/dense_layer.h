// A bias-free dense layer Y = X Wᵀ and its backward pass, for the small MLPs of the neural laws.
//
// The laws evaluate 13 → 64 → 64 → 9 networks on ~1000 particles per substep, 18 small matrix
// products per substep forward and backward. LibTorch sends them to the system BLAS, which on the
// project's Debian machines is the reference (netlib) BLAS: 19 of ~28 ms per training substep
// went to aten::mm (measured with LibTorch's profiler on the training scene, one thread). Every
// loop here is an axpy over a contiguous row, which compilers vectorise without reassociating
// floating-point sums, so results do not depend on the vector width.
//
// Layout: row-major. X [rows, inputs], W [outputs, inputs] (as torch::nn::Linear), Y [rows, outputs].
#pragma once

#include "kernels/core/exec.h"
#include "kernels/core/span.h"

namespace romp::mlp {

struct DenseShape {
  Index rows = 0;
  int inputs = 0, outputs = 0;
};

// Y = X Wᵀ, with W given transposed: W_t [inputs, outputs].
template <class T>
void dense_forward(const Exec& exec, const DenseShape& shape, Span<const T> X, Span<const T> W_t, Span<T> Y);

// dX = dY W [rows, inputs] and dW = dYᵀ X [outputs, inputs] for the layer's output gradient dY.
template <class T>
void dense_backward(const Exec& exec, const DenseShape& shape, Span<const T> X, Span<const T> W, Span<const T> dY,
                    Span<T> dX, Span<T> dW);

}  // namespace romp::mlp
