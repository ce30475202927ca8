// Invariant features and polar rotation of F for the neural laws, with the SVD's autograd function.
#include "nn/nclaw/features.h"

#include "kernels/core/error.h"
#include "nn/svd_ops.h"

namespace romp::nn::nclaw {
namespace {

using torch::autograd::AutogradContext;
using torch::autograd::variable_list;

// F [9, n] → (σ [3, n], R [9, n]), backward through svd3_backward (σ only) + polar3_backward (R only).
class StretchRotationFunction : public torch::autograd::Function<StretchRotationFunction> {
 public:
  static variable_list forward(AutogradContext* ctx, const torch::Tensor& planes) {
    const torch::Tensor F = planes.contiguous();
    const Svd3Tensors svd = svd3(F);
    const torch::Tensor R =
        matrices_to_planes(torch::bmm(planes_to_matrices(svd.U), planes_to_matrices(svd.V).transpose(1, 2)));
    ctx->save_for_backward({F, svd.U, svd.S, svd.V});
    // A positive diagonal F, above all the rest state F = I every simulation starts from, has the
    // exact decomposition σ = its diagonal sorted, R = I. romp's SVD is accurate to a few ulp only
    // (approximate rsqrt, a fixed Jacobi angle for equal diagonal entries), and the laws are
    // stress-free at rest only if σ − 1 is exactly 0 there. The backward pass keeps the SVD's terms.
    const torch::Tensor diagonal = F.index_select(0, torch::tensor({0, 4, 8}, torch::kLong).to(F.device()));
    const torch::Tensor off_diagonal =
        F.index_select(0, torch::tensor({1, 2, 3, 5, 6, 7}, torch::kLong).to(F.device()));
    const torch::Tensor exact = (off_diagonal == 0).all(0) & (diagonal > 0).all(0);
    const torch::Tensor identity = torch::eye(3, F.options()).reshape({9, 1});
    return {torch::where(exact, std::get<0>(diagonal.sort(0, /*descending=*/true)), svd.S),
            torch::where(exact, identity, R)};
  }

  static variable_list backward(AutogradContext* ctx, variable_list gradients) {
    const variable_list saved = ctx->get_saved_variables();
    const torch::Tensor& F = saved[0];
    const torch::Tensor sigma_gradient = gradients[0].contiguous(), R_gradient = gradients[1].contiguous();
    return {svd3_backward(saved[1], saved[2], saved[3], torch::Tensor(), sigma_gradient, torch::Tensor()) +
            polar3_backward(F, R_gradient, torch::Tensor())};
  }
};

}  // namespace

torch::Tensor planes_to_matrices(const torch::Tensor& planes) {
  ROMP_CHECK(planes.dim() == 2 && planes.size(0) == 9,
             "planes_to_matrices: expected [9, n], got " + c10::str(planes.sizes()));
  return planes.t().reshape({-1, 3, 3}).contiguous();
}

torch::Tensor matrices_to_planes(const torch::Tensor& matrices) {
  ROMP_CHECK(matrices.dim() == 3 && matrices.size(1) == 3 && matrices.size(2) == 3,
             "matrices_to_planes: expected [n, 3, 3], got " + c10::str(matrices.sizes()));
  return matrices.reshape({-1, 9}).t().contiguous();
}

StretchRotation stretch_and_rotation(const torch::Tensor& F) {
  const variable_list out = StretchRotationFunction::apply(F);
  return {out[0].t(), planes_to_matrices(out[1])};
}

torch::Tensor invariant_features(const torch::Tensor& F, const torch::Tensor& sigma) {
  const int64_t n = F.size(0);
  const torch::Tensor identity = torch::eye(3, F.options());
  const torch::Tensor cauchy_green = torch::bmm(F.transpose(1, 2), F) - identity;
  // det F as the triple product of the rows: a polynomial, exact at F = I and smooth everywhere
  // (torch::det goes through an LU factorisation and its backward through an inverse).
  const torch::Tensor det = (F.select(1, 0) * torch::cross(F.select(1, 1), F.select(1, 2), 1)).sum(1, true);
  return torch::cat({sigma - 1.0, cauchy_green.reshape({n, 9}), det - 1.0}, 1);
}

}  // namespace romp::nn::nclaw
