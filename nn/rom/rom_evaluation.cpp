// Reconstruction errors: sums of squared errors and of squared truths over a set, in chunks of snapshots.
#include "nn/rom/rom_evaluation.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace romp::nn::rom {
namespace {

double relative(double error, double truth) {
  return truth > 0.0 ? std::sqrt(error / truth) : std::numeric_limits<double>::quiet_NaN();
}

torch::Tensor squared_sum(const torch::Tensor& t) { return t.to(torch::kFloat64).square().sum(); }

}  // namespace

ReconstructionErrors reconstruction_errors(const RomModel& model, const torch::Tensor& X_all, const SnapshotSet& set,
                                           DerivativeMethod method, std::int64_t points) {
  if (set.size() == 0) return {};
  torch::NoGradGuard no_grad;
  const torch::Tensor chosen =
      torch::arange(0, X_all.size(0), evaluation_stride(X_all.size(0), points), X_all.options().dtype(torch::kInt64));
  const torch::Tensor X = X_all.index_select(0, chosen);
  const std::int64_t particles = X.size(0);
  const std::int64_t chunk = std::max<std::int64_t>(1, kEvaluationRows / particles);
  // Sums of squared errors and truths: position, F, velocity.
  torch::Tensor sums = torch::zeros({6}, X.options().dtype(torch::kFloat64));
  for (std::int64_t begin = 0; begin < set.size(); begin += chunk) {
    const std::int64_t count = std::min(chunk, set.size() - begin);
    const torch::Tensor index = torch::arange(begin, begin + count, X.options().dtype(torch::kInt64));
    const torch::Tensor snapshots = set.x.index_select(0, index);
    const torch::Tensor xhat = model.encode(snapshots);
    const torch::Tensor x = snapshots.index_select(1, chosen);
    const torch::Tensor xhat_next = model.encode(set.x.index_select(0, set.next.index_select(0, index)));
    const torch::Tensor rate = (xhat_next - xhat) / set.dt.index_select(0, index).unsqueeze(1);
    const ManifoldJacobians j =
        manifold_jacobians(*model.map, xhat.repeat_interleave(particles, 0), X.repeat({count, 1}),
                           rate.repeat_interleave(particles, 0).unsqueeze(2), method, /*create_graph=*/false);
    const torch::Tensor v = set.frame_velocity.index_select(0, index).index_select(1, chosen).reshape({-1, 3});
    const torch::Tensor F = set.F.index_select(0, index).index_select(1, chosen).reshape({-1, 3, 3});
    const torch::Tensor counts = set.has_next.index_select(0, index).repeat_interleave(particles).unsqueeze(1);
    sums += torch::stack({squared_sum(j.x - x.reshape({-1, 3})), squared_sum(x), squared_sum(j.F - F), squared_sum(F),
                          squared_sum((j.dx.squeeze(2) - v) * counts), squared_sum(v * counts)});
  }
  const torch::Tensor host = sums.cpu();
  const double* s = host.data_ptr<double>();
  return {relative(s[0], s[1]), relative(s[2], s[3]), relative(s[4], s[5])};
}

}  // namespace romp::nn::rom
