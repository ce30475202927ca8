// mlp suite: the deformation map g, ∇_X g and ∂g/∂x̂ at 1k, 20k and 200k points (ROM paper, Sec. 4;
// the paper's r = 6, 5 hidden layers of 30): romp's fused kernel against LibTorch's path (the analytic
// layer Jacobians training uses), the same map on the same device.
#include <fmt/format.h>
#include <torch/torch.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "bench/suites/suites.h"
#include "kernels/core/device_buffer.h"
#include "kernels/rom/deformation_map_eval.h"
#include "nn/rom/fused_map.h"
#include "nn/rom/manifold_derivatives.h"

namespace romp::bench {
namespace {

using nn::rom::DeformationMap;
using nn::rom::MapArchitecture;
using nn::rom::MapNormalisation;

// Reference points in the unit box and one x̂, from a fixed seed.
struct Batch {
  std::vector<float> X_planes;  // 3 planes of n
  std::vector<float> X_rows;    // n rows of 3, for LibTorch
  std::vector<float> xhat;
};

Batch random_batch(Index n, int latent) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Batch b;
  b.X_planes.resize(std::size_t(3 * n));
  b.X_rows.resize(std::size_t(3 * n));
  for (Index p = 0; p < n; ++p)
    for (int a = 0; a < 3; ++a) b.X_rows[std::size_t(3 * p + a)] = b.X_planes[std::size_t(a * n + p)] = unit(random);
  for (int j = 0; j < latent; ++j) b.xhat.push_back(unit(random) - 0.5f);
  return b;
}

}  // namespace

void run_mlp_suite(Context& context) {
  const MapArchitecture architecture{6, 5, 30};
  const auto ones = torch::ones({3}), zeros = torch::zeros({3});
  torch::manual_seed(0);
  DeformationMap map(architecture, MapNormalisation{zeros, ones, zeros, 0.05f * ones});
  const rom::DeformationMapWeights weights = nn::rom::fused_weights(*map);
  const int r = weights.latent;

  for (const Index nominal : {Index(1000), Index(20000), Index(200000)}) {
    const Index n = context.scaled(nominal, 100);
    const Batch batch = random_batch(n, r);
    for (const Exec& exec : context.execs()) {
      const Backend backend = exec.backend;
      const auto parameters = DeviceBuffer<float>::from_host(backend, weights.parameters, exec.stream);
      const auto X = DeviceBuffer<float>::from_host(backend, batch.X_planes, exec.stream);
      const auto xhat = DeviceBuffer<float>::from_host(backend, batch.xhat, exec.stream);
      DeviceBuffer<float> x(backend, 3 * n), F(backend, 9 * n), dg(backend, 3 * r * n);
      const rom::DeformationMapView<float> view =
          rom::map_view(weights, Span<const float>(parameters.data(), parameters.size()));
      const std::string size = fmt::format("{}k", nominal / 1000);
      const auto evaluate = [&](rom::MapKernel kernel) {
        rom::evaluate_deformation_map<float>(
            exec, view, Span<const float>(xhat.data(), r), Vec3Planes<const float>(X.data(), n),
            {Vec3Planes<float>(x.data(), n), Mat3Planes<float>(F.data(), n), dg.span()}, kernel);
      };
      // Both fused kernels (rom::MapKernel): the fixed-shape one for the paper's sizes and the generic one;
      // the engine runs the faster for the backend (MapKernel::Fastest). context.time returns a reference
      // into a vector that the next measurement may move: keep copies.
      const Measurement fixed = context.time(
          "mlp", "fixed_" + size, exec, n, "point", [&] { evaluate(rom::MapKernel::Fixed); }, 0.0,
          "g, grad_X g and dg/dxhat; r = 6, 5 x 30 ELU; fixed-shape kernel");
      const Measurement generic = context.time(
          "mlp", "generic_" + size, exec, n, "point", [&] { evaluate(rom::MapKernel::Generic); }, 0.0,
          "the same with the generic kernel (any sizes; the reference)");
      const double fused_seconds = std::min(fixed.median_seconds(), generic.median_seconds());

      const torch::Device device =
          exec.is_cuda() ? torch::Device(torch::kCUDA, exec.device) : torch::Device(torch::kCPU);
      const int torch_threads = torch::get_num_threads();
      if (!exec.is_cuda()) torch::set_num_threads(exec.threads);
      map->to(device);
      const torch::Tensor X_rows =
          torch::from_blob(const_cast<float*>(batch.X_rows.data()), {n, 3}, torch::kFloat32).to(device);
      const torch::Tensor xhat_rows =
          torch::from_blob(const_cast<float*>(batch.xhat.data()), {1, r}, torch::kFloat32).to(device).expand({n, r});
      torch::NoGradGuard no_gradients;
      const Measurement libtorch = context.time(
          "mlp", "libtorch_" + size, exec, n, "point",
          [&] { nn::rom::manifold_jacobians(*map, xhat_rows, X_rows, nn::rom::DerivativeMethod::Analytic, false); },
          0.0, "the training path's analytic layer Jacobians, no graph");
      torch::set_num_threads(torch_threads);
      context.record(fmt::format("mlp.{}.{}{}.fused_speedup", size, fixed.backend, fixed.threads),
                     libtorch.median_seconds() / fused_seconds);
      context.record(fmt::format("mlp.{}.{}{}.fixed_speedup_over_generic", size, fixed.backend, fixed.threads),
                     generic.median_seconds() / fixed.median_seconds());
    }
  }
}

}  // namespace romp::bench
