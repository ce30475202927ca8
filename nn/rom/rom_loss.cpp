// Eq. (31) on a mini-batch, with the exact derivatives of the map kept in the graph.
#include "nn/rom/rom_loss.h"

namespace romp::nn::rom {

LossTerms rom_loss(const DeformationMapImpl& g, const LossBatch& batch, const LossWeights& weights,
                   DerivativeMethod method) {
  // The velocity term needs ∂g/∂x̂ along one direction only: the finite-difference rate of x̂.
  const ManifoldJacobians j =
      manifold_jacobians(g, batch.xhat, batch.X, batch.xhat_rate.unsqueeze(2), method, /*create_graph=*/true);
  const torch::Tensor scale = g.u_std().norm();
  LossTerms terms;
  terms.position = ((j.x - batch.x) / scale).square().sum(1).mean();
  terms.F = (j.F - batch.F).square().sum({1, 2}).mean();
  const torch::Tensor velocity_error = ((j.dx.squeeze(2) - batch.v) / scale).square().sum(1) * batch.has_next;
  terms.velocity = velocity_error.sum() / batch.has_next.sum().clamp_min(1);
  terms.total = terms.position + weights.F * terms.F + weights.velocity * terms.velocity;
  return terms;
}

}  // namespace romp::nn::rom
