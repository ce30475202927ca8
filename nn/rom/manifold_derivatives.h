// Exact derivatives of the deformation map: the deformation gradient ∇_X g (Eq. (21)) and the tangent ∂g/∂x̂
// (Eq. (22)), by forward-mode differentiation through the MLP's layers or by reverse-mode autograd.
#pragma once

#include <torch/torch.h>

#include "nn/rom/deformation_map.h"
#include "nn/rom/training_record.h"

namespace romp::nn::rom {

struct ManifoldJacobians {
  torch::Tensor x;   // [N, 3] g(X, x̂)
  torch::Tensor F;   // [N, 3, 3] ∇_X g: F[n][i][j] = ∂x_i/∂X_j
  torch::Tensor dx;  // [N, 3, m] (∂g/∂x̂) · directions
};

// g, ∇_X g and ∂g/∂x̂ applied to m directions per point: xhat [N, r], X [N, 3], directions [N, r, m]. With
// `create_graph` the results carry gradients back to the map's parameters, x̂ and the directions (training);
// without, they are detached.
ManifoldJacobians manifold_jacobians(const DeformationMapImpl& g, const torch::Tensor& xhat, const torch::Tensor& X,
                                     const torch::Tensor& directions, DerivativeMethod method, bool create_graph);

// The same with the full ∂g/∂x̂: dx is [N, 3, r].
ManifoldJacobians manifold_jacobians(const DeformationMapImpl& g, const torch::Tensor& xhat, const torch::Tensor& X,
                                     DerivativeMethod method, bool create_graph);

}  // namespace romp::nn::rom
