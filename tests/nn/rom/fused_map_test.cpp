// The fused evaluator (kernels/rom) reading a LibTorch map packed by fused_weights: g, ∇_X g and ∂g/∂x̂
// agree with LibTorch's own evaluation to 1e-5 relative, for the paper's network and the linear baseline.
#include "nn/rom/fused_map.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "nn/rom/manifold_derivatives.h"

namespace romp::nn::rom {
namespace {

// max |a − b| / max |b| over every entry.
double relative_difference(const torch::Tensor& a, const torch::Tensor& b) {
  return (a - b).abs().max().item<double>() / b.abs().max().item<double>();
}

void expect_agreement(const MapArchitecture& architecture) {
  torch::manual_seed(3);
  const MapNormalisation normalisation{torch::tensor({-0.1f, 0.2f, 0.05f}), torch::tensor({0.2f, 0.6f, 0.25f}),
                                       torch::tensor({0.01f, -0.02f, 0.0f}), torch::tensor({0.03f, 0.05f, 0.02f})};
  DeformationMap map(architecture, normalisation);
  {
    // Training leaves non-zero biases: give them some, so hidden units sit on both sides of ELU's kink.
    torch::NoGradGuard no_gradients;
    for (const torch::nn::Linear& layer : map->layers()) layer->bias.uniform_(-0.5, 0.5);
  }
  const std::int64_t n = 400, r = architecture.latent;
  const torch::Tensor X = normalisation.X_min + torch::rand({n, 3}) * (normalisation.X_max - normalisation.X_min);
  const torch::Tensor xhat = torch::rand({1, r}) - 0.5;
  const ManifoldJacobians reference =
      manifold_jacobians(*map, xhat.expand({n, r}), X, DerivativeMethod::Analytic, false);

  const romp::rom::DeformationMapWeights weights = fused_weights(*map);
  const Exec exec = Exec::cpu();
  const auto parameters = DeviceBuffer<float>::from_host(Backend::Cpu, weights.parameters);
  const torch::Tensor X_planes = X.t().contiguous();
  const torch::Tensor xhat_values = xhat.squeeze(0).contiguous();
  torch::Tensor x = torch::empty({3, n}), F = torch::empty({9, n}), dg = torch::empty({3 * r, n});
  const romp::rom::DeformationMapView<float> view =
      romp::rom::map_view(weights, Span<const float>(parameters.data(), parameters.size()));
  romp::rom::evaluate_deformation_map<float>(
      exec, view, Span<const float>(xhat_values.data_ptr<float>(), r),
      Vec3Planes<const float>(X_planes.data_ptr<float>(), n),
      {Vec3Planes<float>(x.data_ptr<float>(), n), Mat3Planes<float>(F.data_ptr<float>(), n),
       Span<float>(dg.data_ptr<float>(), 3 * r * n)});

  EXPECT_LT(relative_difference(x.t(), reference.x), 1e-5);
  EXPECT_LT(relative_difference(F.t().reshape({n, 3, 3}), reference.F), 1e-5);
  EXPECT_LT(relative_difference(dg.t().reshape({n, 3, r}), reference.dx), 1e-5);
}

TEST(FusedMap, PaperNetworkAgreesWithLibTorch) { expect_agreement(MapArchitecture{6, 5, 30}); }

TEST(FusedMap, LinearBaselineAgreesWithLibTorch) { expect_agreement(MapArchitecture{6, 0, 30}); }

}  // namespace
}  // namespace romp::nn::rom
