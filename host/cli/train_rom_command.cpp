// `romp train-rom`: options, device choice, the progress line, Ctrl-C and the model file.
#include "host/cli/train_rom_command.h"

#include <fmt/format.h>
#include <omp.h>
#include <spdlog/spdlog.h>
#include <torch/torch.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "host/build_info.h"
#include "host/cli/exit_codes.h"
#include "host/run/interrupt.h"
#include "kernels/core/error.h"
#include "nn/io/unusable_file_error.h"
#include "nn/rom/rom_checkpoint.h"
#include "nn/rom/rom_dataset.h"
#include "nn/rom/rom_model_file.h"
#include "nn/rom/rom_trainer.h"

namespace romp::cli {
namespace {

std::string percent(double value) { return std::isnan(value) ? "n/a" : fmt::format("{:.3g}%", 100.0 * value); }

std::string errors_text(const nn::rom::ReconstructionErrors& e) {
  return fmt::format("x {}, F {}, v {}", percent(e.position), percent(e.F), percent(e.velocity));
}

// "epoch 20/1000  lr 1e-03  loss 3.1e-03 (x 2.0e-05, F 3.0e-05, v 1.2e-02)  test x 0.81%, F 2.3%, v 14% (256 of
// 1867 points)  epoch 0.55 s, 12.3 s, ETA 605 s"
void print_report(const nn::rom::EpochReport& r) {
  const double per_epoch = r.seconds / double(r.epoch - r.started_at);
  const std::string test = !r.test ? "n/a (no test members)"
                           : r.test_points < r.points
                               ? fmt::format("{} ({} of {} points)", errors_text(*r.test), r.test_points, r.points)
                               : errors_text(*r.test);
  fmt::print(
      "epoch {}/{}  lr {:.0e}  loss {:.3e} (x {:.2e}, F {:.2e}, v {:.2e})  test {}  epoch {:.2f} s, {:.1f} s, ETA "
      "{:.0f} "
      "s{}\n",
      r.epoch, r.epochs, r.learning_rate, r.loss, r.position, r.F, r.velocity, test, r.epoch_seconds, r.seconds,
      per_epoch * double(r.epochs - r.epoch), r.checkpointed ? "  [checkpoint]" : "");
  std::fflush(stdout);
}

torch::Device training_device(DeviceChoice choice, int threads) {
  const Exec exec = select_backend(choice, threads);
  if (!exec.is_cuda()) return torch::kCPU;
  if (!torch::cuda::is_available())
    throw Error("the CUDA device answers, but this LibTorch was built without CUDA; train with --device cpu");
  return torch::Device(torch::kCUDA, static_cast<c10::DeviceIndex>(exec.device));
}

}  // namespace

CLI::App* add_train_rom_command(CLI::App& app, TrainRomOptions& options) {
  nn::rom::TrainingSettings& s = options.settings;
  CLI::App* command = app.add_subcommand(
      "train-rom", "Train the ROM's deformation map g and encoder e on a sweep's snapshots (ROM paper, Sec. 4)");
  command->add_option("sweep", options.sweep_dir, "Sweep folder written by romp sweep")
      ->required()
      ->check(CLI::ExistingDirectory);
  command->add_option("-o,--output", options.output, "Model file (.h5); its checkpoint is <file>.checkpoint")
      ->required();
  command->add_option("--latent", s.architecture.latent, "r, the number of generalized coordinates")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  command->add_flag_callback(
      "--linear", [&s] { s.architecture.hidden_layers = 0; },
      "Linear manifold baseline: g is one affine layer (paper Sec. 5.4.1)");
  command->add_option("--epochs", s.epochs, "Training epochs (passes over the training snapshots)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command->add_option("--batch", s.batch, "Snapshots per mini-batch")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command->add_option("--points", s.points, "Material points per snapshot in each mini-batch's loss")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command->add_option("--encoder-points", s.encoder_points, "Material points the encoder reads (0: all)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command->add_option("--seed", s.seed, "Seed of initialisation, batches and encoder points")->capture_default_str();
  command->add_option("--lambda-F", s.loss_weights.F, "Weight of the deformation-gradient term of Eq. (31)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command->add_option("--lambda-v", s.loss_weights.velocity, "Weight of the velocity term of Eq. (31)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command->add_option("--learning-rate", s.learning_rate, "First stage's learning rate; tenfold drops at --decay-at")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command->add_option("--decay-at", s.decay_at, "Fractions of the epochs where the learning rate drops tenfold")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  command
      ->add_option_function<std::string>(
          "--derivatives",
          [&s](const std::string& method) {
    s.derivatives = method == "autograd" ? nn::rom::DerivativeMethod::Autograd : nn::rom::DerivativeMethod::Analytic;
          },
          "How ∇_X g and ∂g/∂x̂ are computed: analytic (forward tangents, default) or autograd")
      ->check(CLI::IsMember({"analytic", "autograd"}));
  command->add_flag("--resume", options.resume, "Continue from <output>.checkpoint with the same sweep and options");
  command->add_option("--checkpoint-every", options.checkpoint_every, "Epochs between checkpoints (0: none)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command->add_option("--report-every", options.report_every, "Epochs between progress lines with test errors")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  return command;
}

int train_rom_command(DeviceChoice choice, int threads, const TrainRomOptions& options) {
  // LibTorch's own default thread count can be below OpenMP's (Debian's LibTorch 1.13 on a 2-core machine: 1).
  torch::set_num_threads(threads > 0 ? threads : omp_get_max_threads());
  const torch::Device device = training_device(choice, threads);
  nn::rom::TrainOptions train;
  train.settings = options.settings;
  train.report_every = options.report_every;
  train.checkpoint = nn::rom::rom_checkpoint_path(options.output);
  train.checkpoint_every = options.checkpoint_every;
  train.resume = options.resume;

  // As `romp run --resume`: a finished model has nothing to resume.
  if (options.resume && !std::filesystem::exists(train.checkpoint) && std::filesystem::exists(options.output)) {
    spdlog::info("{} is complete; nothing to resume", options.output);
    return 0;
  }
  nn::rom::RomDataset data;
  try {
    if (options.resume && !std::filesystem::exists(train.checkpoint))
      throw io::UnusableFileError("--resume: no checkpoint " + train.checkpoint + " (a run stopped early leaves one)");
    data = nn::rom::load_rom_dataset(options.sweep_dir, {train.settings.encoder_points, train.settings.seed, device});
  } catch (const Error& error) {
    spdlog::error("{}", error.what());
    return kExitInvalidInput;
  }
  spdlog::info("sweep {}: {} material points, {} training and {} test snapshots, encoder reads {}; training on {}",
               options.sweep_dir, data.particle_count(), data.train.size(), data.test.size(),
               data.encoder_indices.size(0), device.str());

  run::install_interrupt_handler();
  const nn::rom::TrainResult result = nn::rom::train_rom(data, train, print_report, run::interrupt_requested);
  if (result.interrupted) {
    spdlog::warn("interrupted after epoch {}; continue with --resume (checkpoint {})",
                 result.model.training.epochs_done, train.checkpoint);
    return run::kExitInterrupted;
  }
  nn::rom::RomModel model = result.model;
  model.training.romp_version = build_info().version;
  model.training.commit = build_info().commit;
  nn::rom::write_rom_model(options.output, model);
  std::filesystem::remove(train.checkpoint);
  fmt::print("{}: trained {} epochs; reconstruction errors (relative L2): train {}; test {}\n", options.output,
             model.training.epochs_done, errors_text(model.training.train_errors),
             errors_text(model.training.test_errors));
  return 0;
}

}  // namespace romp::cli
