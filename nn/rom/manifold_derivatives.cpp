// ∇_X g and ∂g/∂x̂ by forward-mode tangents through the layers, or by reverse-mode autograd.
//
// Both give the same training to the printed digits. Measured (bench/results/2026-12-01-rom-train-cpu, one CPU
// thread, LibTorch on Debian's reference BLAS): autograd 6.3 s and tangents 7.0 s per epoch of the gravity
// sweep, a tie within the noise on torsion. Tangents stay the default because they are the formulation the
// fused evaluation kernel computes, so training and online evaluation share one derivation.
#include "nn/rom/manifold_derivatives.h"

#include <string>
#include <vector>

#include "kernels/core/error.h"

namespace romp::nn::rom {
namespace {

// Tangents ride along the values as [3 + m, N, width]: the three X directions first, then the m x̂ directions.
// x = X + u_mean + u_std ⊙ out(x̂, (X − X_min) / extent), so ∂x/∂X = I + u_std ⊙ ∂out/∂X̄ / extent.
ManifoldJacobians analytic(const DeformationMapImpl& g, const torch::Tensor& xhat, const torch::Tensor& X,
                           const torch::Tensor& directions) {
  const std::vector<torch::nn::Linear>& layers = g.layers();
  const std::int64_t r = g.architecture().latent;
  const std::int64_t n = X.size(0);
  const torch::Tensor& W0 = layers[0]->weight;
  torch::Tensor a = torch::linear(g.network_input(xhat, X), W0, layers[0]->bias);
  // The input's tangents are unit vectors, so the first layer's are columns of W0: the X columns are the
  // same for every point, the x̂ ones are the directions mapped through W0's x̂ columns.
  const torch::Tensor X_tangent = (W0.slice(1, r, r + 3) / g.X_extent()).t().unsqueeze(1).expand({3, n, W0.size(0)});
  const torch::Tensor xhat_tangent = directions.permute({2, 0, 1}).matmul(W0.slice(1, 0, r).t());
  torch::Tensor da = torch::cat({X_tangent, xhat_tangent}, 0);
  for (std::size_t k = 1; k < layers.size(); ++k) {
    const torch::Tensor h = torch::elu(a);
    // ELU'(a) = 1 for a > 0 and e^a = ELU(a) + 1 otherwise.
    const torch::Tensor slope = 1 + h.clamp_max(0);
    a = torch::linear(h, layers[k]->weight, layers[k]->bias);
    da = (da * slope).matmul(layers[k]->weight.t());
  }
  const torch::Tensor tangent = da * g.u_std();  // [3 + m, N, 3]
  ManifoldJacobians result;
  result.x = g.position(X, a);
  result.F = tangent.slice(0, 0, 3).permute({1, 2, 0}) + torch::eye(3, X.options());
  result.dx = tangent.slice(0, 3).permute({1, 2, 0});
  return result;
}

ManifoldJacobians autograd(const DeformationMapImpl& g, const torch::Tensor& xhat, const torch::Tensor& X,
                           const torch::Tensor& directions, bool create_graph) {
  torch::AutoGradMode enabled(true);
  const torch::Tensor X_leaf = X.detach().requires_grad_(true);
  // x̂ from the encoder stays in its graph when training; otherwise a leaf to differentiate against.
  const torch::Tensor xhat_in = create_graph && xhat.requires_grad() ? xhat : xhat.detach().requires_grad_(true);
  const torch::Tensor x = g.forward(xhat_in, X_leaf);
  std::vector<torch::Tensor> F_rows, xhat_rows;
  for (std::int64_t i = 0; i < 3; ++i) {
    const torch::Tensor component = x.select(1, i);
    const std::vector<torch::Tensor> rows = torch::autograd::grad(
        {component}, {X_leaf, xhat_in}, {torch::ones_like(component)}, /*retain_graph=*/true, create_graph);
    F_rows.push_back(rows[0]);
    xhat_rows.push_back(rows[1]);
  }
  ManifoldJacobians result{x, torch::stack(F_rows, 1), torch::stack(xhat_rows, 1).matmul(directions)};
  if (!create_graph) {
    result.x = result.x.detach();
    result.F = result.F.detach();
    result.dx = result.dx.detach();
  }
  return result;
}

}  // namespace

ManifoldJacobians manifold_jacobians(const DeformationMapImpl& g, const torch::Tensor& xhat, const torch::Tensor& X,
                                     const torch::Tensor& directions, DerivativeMethod method, bool create_graph) {
  const std::int64_t r = g.architecture().latent;
  ROMP_CHECK(directions.dim() == 3 && directions.size(0) == X.size(0) && directions.size(1) == r,
             "manifold derivatives: directions must be [N, " + std::to_string(r) + ", m]");
  if (method == DerivativeMethod::Autograd) return autograd(g, xhat, X, directions, create_graph);
  if (create_graph) return analytic(g, xhat, X, directions);
  torch::NoGradGuard no_grad;
  return analytic(g, xhat, X, directions);
}

ManifoldJacobians manifold_jacobians(const DeformationMapImpl& g, const torch::Tensor& xhat, const torch::Tensor& X,
                                     DerivativeMethod method, bool create_graph) {
  const std::int64_t r = g.architecture().latent;
  const torch::Tensor identity = torch::eye(r, xhat.options()).expand({X.size(0), r, r});
  return manifold_jacobians(g, xhat, X, identity, method, create_graph);
}

}  // namespace romp::nn::rom
