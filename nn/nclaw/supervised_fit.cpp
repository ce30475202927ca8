// add_plastic_pairs and fit_supervised.
#include "nn/nclaw/supervised_fit.h"

#include <string>

#include "kernels/core/error.h"
#include "nn/nclaw/features.h"
#include "nn/nclaw/training_schedule.h"

namespace romp::nn::nclaw {
namespace {

torch::Tensor appended(const torch::Tensor& existing, const torch::Tensor& more) {
  return existing.defined() ? torch::cat({existing, more}, 1) : more;
}

// Relative mean squared error of `prediction` against `target`, scaled by the mean square of `scale`.
torch::Tensor relative_mse(const torch::Tensor& prediction, const torch::Tensor& target, const torch::Tensor& scale) {
  return (prediction - target).square().mean() / scale.square().mean().clamp_min(1e-30);
}

void set_learning_rate(torch::optim::Adam& optimizer, double learning_rate) {
  for (torch::optim::OptimizerParamGroup& group : optimizer.param_groups())
    static_cast<torch::optim::AdamOptions&>(group.options()).lr(learning_rate);
}

}  // namespace

void add_plastic_pairs(const Trajectory& truth, double dt, ConstitutivePairs& pairs) {
  truth.validate();
  const int64_t steps = truth.frame_count() - 1, n = truth.particle_count();
  // [steps, 9, n] planes → [steps n, 3, 3] matrices.
  const auto matrices = [&](const torch::Tensor& planes) {
    return planes.permute({0, 2, 1}).reshape({steps * n, 3, 3});
  };
  const torch::Tensor C_next = matrices(truth.C.slice(0, 1)), F_previous = matrices(truth.F.slice(0, 0, steps));
  const torch::Tensor identity = torch::eye(3, truth.F.options());
  pairs.F_trial = appended(pairs.F_trial, matrices_to_planes(torch::bmm(identity + dt * C_next, F_previous)));
  pairs.F_projected = appended(pairs.F_projected, matrices_to_planes(matrices(truth.F.slice(0, 1))));
}

SupervisedLosses fit_supervised(NeuralLaws& laws, const ConstitutivePairs& pairs, const SupervisedOptions& options) {
  ROMP_CHECK(options.epochs > 0, "supervised fit: epochs must be positive, got " + std::to_string(options.epochs));
  const bool elastic = pairs.F.defined(), plastic = pairs.F_trial.defined();
  ROMP_CHECK(elastic || plastic, "supervised fit: no pairs");
  ROMP_CHECK(!elastic || (pairs.P.defined() && pairs.P.sizes() == pairs.F.sizes() && pairs.F.size(0) == 9),
             "supervised fit: F and P must both be [9, m]");
  ROMP_CHECK(!plastic || (pairs.F_projected.defined() && pairs.F_projected.sizes() == pairs.F_trial.sizes() &&
                          pairs.F_trial.size(0) == 9),
             "supervised fit: F_trial and F_projected must both be [9, m]");
  torch::optim::Adam elastic_optimizer(laws.elastic->parameters(),
                                       torch::optim::AdamOptions(options.elastic_learning_rate));
  torch::optim::Adam plastic_optimizer(laws.plastic->parameters(),
                                       torch::optim::AdamOptions(options.plastic_learning_rate));
  SupervisedLosses losses;
  for (int64_t epoch = 0; epoch < options.epochs; ++epoch) {
    if (elastic) {
      set_learning_rate(elastic_optimizer, cosine_anneal(options.elastic_learning_rate, 0.0, epoch, options.epochs));
      elastic_optimizer.zero_grad();
      const torch::Tensor loss = relative_mse(laws.elastic->forward(pairs.F), pairs.P, pairs.P);
      loss.backward();
      torch::nn::utils::clip_grad_norm_(laws.elastic->parameters(), options.gradient_clip);
      elastic_optimizer.step();
      losses.elastic.push_back(loss.item<double>());
    }
    if (plastic) {
      set_learning_rate(plastic_optimizer, cosine_anneal(options.plastic_learning_rate, 0.0, epoch, options.epochs));
      plastic_optimizer.zero_grad();
      const torch::Tensor loss =
          relative_mse(laws.plastic->forward(pairs.F_trial), pairs.F_projected, pairs.F_projected - pairs.F_trial);
      loss.backward();
      torch::nn::utils::clip_grad_norm_(laws.plastic->parameters(), options.gradient_clip);
      plastic_optimizer.step();
      losses.plastic.push_back(loss.item<double>());
    }
  }
  return losses;
}

}  // namespace romp::nn::nclaw
