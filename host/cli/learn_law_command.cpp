// learn-law: ground truth → LawTrainer epochs with checkpoints → law file.
#include "host/cli/learn_law_command.h"

#include <fmt/format.h>
#include <omp.h>
#include <spdlog/spdlog.h>

#include <filesystem>

#include "host/nclaw/ground_truth.h"
#include "host/nclaw/oracles.h"
#include "host/run/interrupt.h"
#include "kernels/core/error.h"
#include "nn/io/atomic_file.h"
#include "nn/io/unusable_file_error.h"
#include "nn/nclaw/evaluation.h"
#include "nn/nclaw/law_file.h"
#include "nn/nclaw/law_trainer.h"
#include "nn/tensor_bridge.h"

namespace romp::cli {

CLI::App* add_learn_law_command(CLI::App& app, LearnLawOptions& options) {
  CLI::App* command = app.add_subcommand("learn-law", "Learn neural elastic and plastic laws from a trajectory");
  command->add_option("trajectory", options.trajectory, "Ground-truth snapshot (.h5) with one frame per substep")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("-o,--output", options.output, "Law file to write (.h5)")->required();
  command->add_option("--epochs", options.epochs, "Training epochs, one rollout each")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command->add_option("--steps", options.steps, "Substeps per rollout")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command
      ->add_option("--checkpoint-every", options.checkpoint_every,
                   "Keep states only this many substeps apart and recompute between them in the backward pass")
      ->check(CLI::NonNegativeNumber);
  command->add_option("--seed", options.seed, "Seed of the initial weights")->capture_default_str();
  command
      ->add_option("--teacher-forcing-first", options.teacher_forcing_first,
                   "Substeps between restarts from the ground truth in the first epoch")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command
      ->add_option("--teacher-forcing-last", options.teacher_forcing_last,
                   "... rising by cosine annealing to this many in the last epoch (the rollout's --steps: no restart)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command
      ->add_option("--velocity-weight", options.velocity_weight,
                   "Add this weight (s^2) times the velocity MSE to the position MSE of every substep (the paper's "
                   "App. Table 7; 0: positions only)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  command->add_flag("--resume", options.resume, "Continue from <output>.checkpoint");
  command
      ->add_option("--method", options.method,
                   "motion: learn from the trajectory's motion; labeled: fit the laws to the ground truth's "
                   "(F, P) and plastic pairs (oracle); system-identification: fit E and nu of fixed corotated "
                   "through the same simulation (oracle; -o names a .toml material table)")
      ->check(CLI::IsMember({"motion", "labeled", "system-identification"}))
      ->capture_default_str();
  command->add_option("--pair-stride", options.pair_stride, "labeled: pairs from every this many frames")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command->add_option("--initial-youngs", options.initial_youngs, "system-identification: first guess of E (Pa)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command->add_option("--initial-poisson", options.initial_poisson, "system-identification: first guess of nu")
      ->check(CLI::Range(0.0, 0.5))
      ->capture_default_str();
  return command;
}

namespace {

// The oracles: fits that know the ground truth's pairs or its model (host/nclaw/oracles.h).
int run_oracle(const nclaw::GroundTruth& truth, const LearnLawOptions& options) {
  if (options.method == "labeled") {
    nn::nclaw::SupervisedOptions supervised;
    supervised.epochs = options.epochs;
    const nn::nclaw::LawFile fitted =
        nclaw::fit_labeled_oracle(truth, options.trajectory, supervised, options.pair_stride, options.seed);
    nn::nclaw::write_law_file(options.output, fitted.laws, fitted.training);
    spdlog::info(
        "wrote {} (labeled oracle, {} epochs: relative stress error {:.3g} -> {:.3g}); reconstruction "
        "error {:.4g} m^2",
        options.output, options.epochs, fitted.training.loss.front(), fitted.training.loss.back(),
        fitted.training.reconstruction_error);
    return 0;
  }
  nn::nclaw::SystemIdentificationOptions identification;
  identification.epochs = options.epochs;
  identification.steps = options.steps;
  identification.initial_youngs = options.initial_youngs;
  identification.initial_poisson = options.initial_poisson;
  const nclaw::IdentifiedMaterial found =
      nclaw::identify_material(truth, identification,
                               [&](int64_t epoch, double loss, double youngs, double poisson) {
    spdlog::info("epoch {}/{}: loss {:.6g}  E = {:.6g} Pa, nu = {:.6g}", epoch, options.epochs, loss, youngs, poisson);
      });
  io::write_file_atomically(
      options.output,
      fmt::format("# romp learn-law --method system-identification {}: fixed corotated fitted through the "
                  "differentiable\n# simulation in {} epochs from E = {} Pa, nu = {}; reconstruction error {:.6g} m^2 "
                  "(mean position MSE "
                  "every {} frames of a free rollout)\n[materials.identified]\nmodel = \"fixed-corotated\"\n"
                  "density = {}\nyoungs_modulus = {:.8g}\npoissons_ratio = {:.8g}\n",
                  options.trajectory, options.epochs, options.initial_youngs, options.initial_poisson,
                  found.reconstruction_error, nn::nclaw::kEvaluationFrameStride, truth.materials.front().density,
                  found.youngs_modulus, found.poissons_ratio));
  spdlog::info("wrote {}: E = {:.6g} Pa, nu = {:.6g}; reconstruction error {:.4g} m^2", options.output,
               found.youngs_modulus, found.poissons_ratio, found.reconstruction_error);
  return 0;
}

}  // namespace

int learn_law_command(DeviceChoice choice, int threads, const LearnLawOptions& options) {
  const std::string extension = options.method == "system-identification" ? ".toml" : ".h5";
  if (std::filesystem::path(options.output).extension() != extension)
    throw CLI::ValidationError(
        "--output", "learn-law --method " + options.method + " writes a " + extension + " file, got " + options.output);
  // Checked before training, not after it: every method ends by measuring the reconstruction error
  // every kEvaluationFrameStride frames of a rollout of --steps substeps.
  if (options.steps < nn::nclaw::kEvaluationFrameStride)
    throw CLI::ValidationError(
        "--steps", "the reconstruction error is measured every " + std::to_string(nn::nclaw::kEvaluationFrameStride) +
                       " substeps, so --steps must be at least that, got " + std::to_string(options.steps));
  const Exec exec = select_backend(choice, threads);
  // The romp kernels behind the autograd functions and LibTorch's own ops share the CPU threads: both get
  // the run's count (LibTorch's own default can be lower, see select_exec).
  const int cpu_threads = exec.is_cuda() ? threads : exec.threads;
  if (cpu_threads > 0) {
    omp_set_num_threads(cpu_threads);
    torch::set_num_threads(cpu_threads);
  }
  if (exec.is_cuda() && !torch::cuda::is_available())
    throw Error("learn-law: the CUDA backend was selected but this LibTorch has no CUDA device; use --device cpu");
  const nclaw::GroundTruth truth = nclaw::read_ground_truth(options.trajectory, options.steps);
  // The oracles are comparison points, run where the trajectory is read: on the CPU.
  if (options.method != "motion") return run_oracle(truth, options);
  const torch::Device device = nn::torch_device(exec);
  nn::nclaw::TrainingOptions training;
  training.epochs = options.epochs;
  training.steps = options.steps;
  training.checkpoint_every = options.checkpoint_every;
  training.seed = options.seed;
  training.teacher_forcing_first = options.teacher_forcing_first;
  training.teacher_forcing_last = options.teacher_forcing_last;
  training.velocity_weight = options.velocity_weight;
  nn::nclaw::LawTrainer trainer(truth.config, truth.trajectory.to(device, torch::kFloat32), training);

  const std::string checkpoint = options.output + ".checkpoint";
  if (options.resume) {
    if (!std::filesystem::exists(checkpoint))
      throw io::UnusableFileError("--resume: no checkpoint " + checkpoint + " (it is removed once " + options.output +
                                  " is written)");
    trainer.load_checkpoint(checkpoint);
    spdlog::info("resumed {} after epoch {}", checkpoint, trainer.epochs_done());
  }
  spdlog::info("learning laws from {}: {} particles, {} substeps per epoch, {} epochs on {}", options.trajectory,
               truth.trajectory.particle_count(), training.steps, training.epochs, device.str());
  // Ctrl-C or SIGTERM ends the epoch under way, whose checkpoint is then the place to resume from.
  run::install_interrupt_handler();
  const int64_t first_epoch = trainer.epochs_done();  // the ETA counts only this process's epochs
  double seconds_so_far = 0.0;
  while (!trainer.finished()) {
    const nn::nclaw::EpochReport r = trainer.train_epoch();
    trainer.save_checkpoint(checkpoint);
    seconds_so_far += r.seconds;
    const double eta = seconds_so_far / double(r.epoch + 1 - first_epoch) * double(training.epochs - r.epoch - 1);
    spdlog::info(
        "epoch {}/{}: loss {:.6g}  teacher forcing every {} substeps  learning rates {:.3g}, {:.3g}  "
        "gradient norms {:.3g}, {:.3g}  {:.2f} s (rollouts {:.2f} s, backward {:.2f} s), ETA {:.0f} s",
        r.epoch + 1, training.epochs, r.loss, r.teacher_forcing_period, r.elastic_learning_rate,
        r.plastic_learning_rate, r.elastic_gradient_norm, r.plastic_gradient_norm, r.seconds, r.forward_seconds,
        r.backward_seconds, eta);
    if (run::interrupt_requested() && !trainer.finished()) {
      spdlog::warn("interrupted after epoch {}; continue with --resume (checkpoint {})", trainer.epochs_done(),
                   checkpoint);
      return run::kExitInterrupted;
    }
  }
  const double reconstruction = trainer.reconstruction_error();
  nn::nclaw::write_law_file(options.output, trainer.laws(),
                            {options.trajectory, training.steps, trainer.losses(), reconstruction});
  std::filesystem::remove(checkpoint);
  spdlog::info("wrote {}; reconstruction error (mean position MSE every {} frames of a free rollout) {:.4g} m^2",
               options.output, nn::nclaw::kEvaluationFrameStride, reconstruction);
  return 0;
}

}  // namespace romp::cli
