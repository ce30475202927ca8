// LawTrainer: the epoch loop of App. D.2 (teacher forcing, 1e4-scaled position MSE, per-network
// clipping, cosine-annealed Adam) and checkpoints of everything it changes.
#include "nn/nclaw/law_trainer.h"

#include <chrono>
#include <cmath>
#include <filesystem>

#include "kernels/core/error.h"
#include "nn/io/unusable_file_error.h"
#include "nn/nclaw/evaluation.h"
#include "nn/nclaw/training_schedule.h"
#include "nn/nclaw/trajectory_loss.h"

namespace romp::nn::nclaw {
namespace {

std::unique_ptr<torch::optim::Adam> adam(const torch::nn::Module& network, double learning_rate) {
  return std::make_unique<torch::optim::Adam>(network.parameters(), torch::optim::AdamOptions(learning_rate));
}

void set_learning_rate(torch::optim::Adam& optimizer, double learning_rate) {
  for (torch::optim::OptimizerParamGroup& group : optimizer.param_groups())
    static_cast<torch::optim::AdamOptions&>(group.options()).lr(learning_rate);
}

// The options a checkpoint must agree on, as one float64 tensor.
torch::Tensor options_fingerprint(const TrainingOptions& o) {
  return torch::tensor(std::vector<double>{double(o.epochs), double(o.steps), o.elastic_learning_rate,
                                           o.plastic_learning_rate, o.gradient_clip, o.loss_scale,
                                           double(o.teacher_forcing_first), double(o.teacher_forcing_last),
                                           double(o.seed), double(o.checkpoint_every), o.velocity_weight},
                       torch::kFloat64);
}

}  // namespace

void TrainingOptions::validate() const {
  ROMP_CHECK(epochs > 0, "training: epochs must be positive, got " + std::to_string(epochs));
  ROMP_CHECK(steps > 0, "training: steps must be positive, got " + std::to_string(steps));
  ROMP_CHECK(elastic_learning_rate > 0.0 && plastic_learning_rate > 0.0, "training: learning rates must be positive");
  ROMP_CHECK(gradient_clip > 0.0, "training: gradient_clip must be positive");
  ROMP_CHECK(loss_scale > 0.0, "training: loss_scale must be positive");
  ROMP_CHECK(teacher_forcing_first > 0 && teacher_forcing_last > 0,
             "training: teacher-forcing periods must be positive, got " + std::to_string(teacher_forcing_first) +
                 " and " + std::to_string(teacher_forcing_last));
  ROMP_CHECK(checkpoint_every >= 0, "training: checkpoint_every must be >= 0");
  ROMP_CHECK(velocity_weight >= 0.0, "training: velocity_weight must be >= 0, got " + std::to_string(velocity_weight));
}

LawTrainer::LawTrainer(const diffmpm::DiffMpmConfig& config, Trajectory truth, const TrainingOptions& options)
    : sim_(config, truth.mass, truth.volume),
      truth_(std::move(truth)),
      options_(options),
      laws_(seeded_laws(options.seed, truth_.mass.options())),
      elastic_optimizer_(adam(*laws_.elastic, options.elastic_learning_rate)),
      plastic_optimizer_(adam(*laws_.plastic, options.plastic_learning_rate)) {
  options_.validate();
  truth_.validate();
  truth_.require_steps(options_.steps, "training");
}

EpochReport LawTrainer::train_epoch() {
  ROMP_CHECK(!finished(), "training: all " + std::to_string(options_.epochs) + " epochs are done");
  const auto started = std::chrono::steady_clock::now();
  EpochReport report;
  report.epoch = epochs_done();
  report.elastic_learning_rate = cosine_anneal(options_.elastic_learning_rate, 0.0, report.epoch, options_.epochs);
  report.plastic_learning_rate = cosine_anneal(options_.plastic_learning_rate, 0.0, report.epoch, options_.epochs);
  report.teacher_forcing_period = teacher_forcing_period(options_.teacher_forcing_first, options_.teacher_forcing_last,
                                                         report.epoch, options_.epochs);

  elastic_optimizer_->zero_grad();
  plastic_optimizer_->zero_grad();
  const TrajectoryLossResult loss =
      backpropagate_trajectory_loss(sim_, truth_, laws_.constitutive(),
                                    {options_.steps, report.teacher_forcing_period, options_.loss_scale,
                                     options_.checkpoint_every, options_.velocity_weight});
  report.loss = loss.value;
  report.forward_seconds = loss.forward_seconds;
  report.backward_seconds = loss.backward_seconds;
  ROMP_CHECK(std::isfinite(report.loss), "training: the loss of epoch " + std::to_string(report.epoch) +
                                             " is not finite; the laws diverged (try smaller learning rates)");

  report.elastic_gradient_norm = torch::nn::utils::clip_grad_norm_(laws_.elastic->parameters(), options_.gradient_clip);
  report.plastic_gradient_norm = torch::nn::utils::clip_grad_norm_(laws_.plastic->parameters(), options_.gradient_clip);
  ROMP_CHECK(std::isfinite(report.elastic_gradient_norm) && std::isfinite(report.plastic_gradient_norm),
             "training: non-finite gradients in epoch " + std::to_string(report.epoch) +
                 ": the laws produced non-finite stress or F (try smaller learning rates)");
  set_learning_rate(*elastic_optimizer_, report.elastic_learning_rate);
  set_learning_rate(*plastic_optimizer_, report.plastic_learning_rate);
  elastic_optimizer_->step();
  plastic_optimizer_->step();
  losses_.push_back(report.loss);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return report;
}

double LawTrainer::reconstruction_error() const {
  return position_error(sim_, truth_, laws_.constitutive(), options_.steps);
}

void LawTrainer::save_checkpoint(const std::string& path) const {
  torch::serialize::OutputArchive archive, elastic, plastic, elastic_adam, plastic_adam;
  laws_.elastic->save(elastic);
  laws_.plastic->save(plastic);
  elastic_optimizer_->save(elastic_adam);
  plastic_optimizer_->save(plastic_adam);
  archive.write("elastic", elastic);
  archive.write("plastic", plastic);
  archive.write("elastic_adam", elastic_adam);
  archive.write("plastic_adam", plastic_adam);
  archive.write("losses", torch::tensor(losses_, torch::kFloat64));
  archive.write("options", options_fingerprint(options_));
  const std::string partial = path + ".partial";
  archive.save_to(partial);
  std::filesystem::rename(partial, path);
}

void LawTrainer::load_checkpoint(const std::string& path) {
  const std::string label = "training checkpoint " + path;
  torch::serialize::InputArchive archive, elastic, plastic, elastic_adam, plastic_adam;
  torch::Tensor losses, options;
  try {
    archive.load_from(path);
    archive.read("options", options);
    archive.read("losses", losses);
  } catch (const c10::Error& error) {
    throw io::UnusableFileError(label + ": not a readable checkpoint (" + error.what_without_backtrace() + ")");
  }
  // A checkpoint of another training, or one whose record no training writes: the input's fault (exit 3).
  if (!(options.sizes() == options_fingerprint(options_).sizes() && options.equal(options_fingerprint(options_)))) {
    throw io::UnusableFileError(label +
                                ": written with other training options (epochs, steps, learning rates, clip, loss "
                                "scale, teacher forcing, seed, checkpoint_every or velocity weight differ)");
  }
  if (!(losses.dim() == 1 && losses.size(0) <= options_.epochs)) {
    throw io::UnusableFileError(label + ": holds " + c10::str(losses.sizes()) + " losses for " +
                                std::to_string(options_.epochs) + " epochs");
  }
  try {
    archive.read("elastic", elastic);
    archive.read("plastic", plastic);
    archive.read("elastic_adam", elastic_adam);
    archive.read("plastic_adam", plastic_adam);
    laws_.elastic->load(elastic);
    laws_.plastic->load(plastic);
    elastic_optimizer_->load(elastic_adam);
    plastic_optimizer_->load(plastic_adam);
  } catch (const c10::Error& error) {
    throw io::UnusableFileError(label + ": weights or optimizer state unreadable (" + error.what_without_backtrace() +
                                ")");
  }
  const torch::Tensor history = losses.to(torch::kFloat64).contiguous();
  losses_.assign(history.data_ptr<double>(), history.data_ptr<double>() + history.numel());
}

}  // namespace romp::nn::nclaw
