// SystemIdentification: fixed corotated stress with learnable E, ν inside the neural laws' training loop.
#include "nn/nclaw/system_identification.h"

#include <cmath>
#include <string>

#include "kernels/core/error.h"
#include "nn/nclaw/fixed_corotated.h"
#include "nn/nclaw/training_schedule.h"
#include "nn/nclaw/trajectory_loss.h"

namespace romp::nn::nclaw {

void SystemIdentificationOptions::validate() const {
  ROMP_CHECK(epochs > 0 && steps > 0, "system identification: epochs and steps must be positive");
  ROMP_CHECK(learning_rate > 0.0, "system identification: learning_rate must be positive");
  ROMP_CHECK(teacher_forcing_first > 0 && teacher_forcing_last > 0,
             "system identification: teacher-forcing periods must be positive");
  ROMP_CHECK(loss_scale > 0.0, "system identification: loss_scale must be positive");
  ROMP_CHECK(initial_youngs > 0.0,
             "system identification: initial_youngs must be positive (Pa), got " + std::to_string(initial_youngs));
  ROMP_CHECK(initial_poisson > 0.0 && initial_poisson < 0.5,
             "system identification: initial_poisson must be in (0, 0.5), got " + std::to_string(initial_poisson));
}

SystemIdentification::SystemIdentification(const diffmpm::DiffMpmConfig& config, Trajectory truth,
                                           const SystemIdentificationOptions& options)
    : sim_(config, truth.mass, truth.volume), truth_(std::move(truth)), options_(options) {
  options_.validate();
  truth_.validate();
  truth_.require_steps(options_.steps, "system identification");
  const auto scalar = truth_.mass.options().requires_grad(true);
  log_youngs_ = torch::tensor(std::log(options_.initial_youngs), scalar);
  // logit(2ν): the inverse of ν = sigmoid(·) / 2.
  poisson_logit_ =
      torch::tensor(std::log(2.0 * options_.initial_poisson / (1.0 - 2.0 * options_.initial_poisson)), scalar);
  optimizer_ = std::make_unique<torch::optim::Adam>(std::vector<torch::Tensor>{log_youngs_, poisson_logit_},
                                                    torch::optim::AdamOptions(options_.learning_rate));
}

torch::Tensor SystemIdentification::youngs_tensor() const { return log_youngs_.exp(); }
torch::Tensor SystemIdentification::poisson_tensor() const { return 0.5 * torch::sigmoid(poisson_logit_); }
double SystemIdentification::youngs() const { return youngs_tensor().item<double>(); }
double SystemIdentification::poisson() const { return poisson_tensor().item<double>(); }

double SystemIdentification::train_epoch() {
  ROMP_CHECK(!finished(), "system identification: all " + std::to_string(options_.epochs) + " epochs are done");
  const int64_t epoch = epochs_done_;
  for (torch::optim::OptimizerParamGroup& group : optimizer_->param_groups())
    static_cast<torch::optim::AdamOptions&>(group.options())
        .lr(cosine_anneal(options_.learning_rate, 0.0, epoch, options_.epochs));
  optimizer_->zero_grad();
  const diffmpm::ConstitutiveLaws law{
      [this](const torch::Tensor& F) { return fixed_corotated_stress(F, youngs_tensor(), poisson_tensor()); },
      {},
      {log_youngs_, poisson_logit_}};
  const double loss =
      backpropagate_trajectory_loss(sim_, truth_, law,
                                    {options_.steps,
                                     teacher_forcing_period(options_.teacher_forcing_first,
                                                            options_.teacher_forcing_last, epoch, options_.epochs),
                                     options_.loss_scale, 0})
          .value;
  ROMP_CHECK(std::isfinite(loss), "system identification: the loss of epoch " + std::to_string(epoch) +
                                      " is not finite (try a smaller learning rate)");
  optimizer_->step();
  ++epochs_done_;
  return loss;
}

}  // namespace romp::nn::nclaw
