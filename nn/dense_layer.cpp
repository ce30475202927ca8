// dense(): checks, then mlp::dense_forward / dense_backward inside a torch::autograd::Function.
#include "nn/dense_layer.h"

#include <string>

#include "kernels/core/error.h"
#include "kernels/mlp/dense_layer.h"
#include "nn/tensor_bridge.h"

namespace romp::nn {
namespace {

using torch::autograd::AutogradContext;
using torch::autograd::variable_list;

mlp::DenseShape shape_of(const torch::Tensor& X, const torch::Tensor& W) {
  return {X.size(0), int(W.size(1)), int(W.size(0))};
}

class DenseFunction : public torch::autograd::Function<DenseFunction> {
 public:
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& input, const torch::Tensor& weight) {
    const torch::Tensor X = input.contiguous(), W = weight.contiguous();
    const mlp::DenseShape shape = shape_of(X, W);
    torch::Tensor Y = torch::empty({shape.rows, shape.outputs}, X.options());
    const torch::Tensor W_t = W.t().contiguous();
    dispatch_real(X, "dense: X", [&](auto scalar) {
      using T = decltype(scalar);
      const Exec exec = exec_for(X);
      mlp::dense_forward<T>(exec, shape, as_span<const T>(X, exec, "dense X"), as_span<const T>(W_t, exec, "dense W"),
                            as_span<T>(Y, exec, "dense Y"));
    });
    ctx->save_for_backward({X, W});
    return Y;
  }

  static variable_list backward(AutogradContext* ctx, variable_list gradients) {
    const variable_list saved = ctx->get_saved_variables();
    const torch::Tensor &X = saved[0], &W = saved[1];
    const torch::Tensor dY = gradients[0].contiguous();
    torch::Tensor dX = torch::empty_like(X), dW = torch::empty_like(W);
    dispatch_real(X, "dense: X", [&](auto scalar) {
      using T = decltype(scalar);
      const Exec exec = exec_for(X);
      mlp::dense_backward<T>(exec, shape_of(X, W), as_span<const T>(X, exec, "dense X"),
                             as_span<const T>(W, exec, "dense W"), as_span<const T>(dY, exec, "dense dY"),
                             as_span<T>(dX, exec, "dense dX"), as_span<T>(dW, exec, "dense dW"));
    });
    return {dX, dW};
  }
};

}  // namespace

torch::Tensor dense(const torch::Tensor& X, const torch::Tensor& W) {
  ROMP_CHECK(X.defined() && W.defined(), "dense: X and W must be defined");
  ROMP_CHECK(X.dim() == 2 && W.dim() == 2 && X.size(1) == W.size(1),
             "dense: X must be [rows, inputs] and W [outputs, inputs], got X " + c10::str(X.sizes()) + " and W " +
                 c10::str(W.sizes()));
  ROMP_CHECK(X.scalar_type() == W.scalar_type() && X.device() == W.device(),
             "dense: X is " + c10::str(X.scalar_type(), " on ", X.device()) + ", W " +
                 c10::str(W.scalar_type(), " on ", W.device()));
  return DenseFunction::apply(X, W);
}

}  // namespace romp::nn
