// The training loop: batches of snapshots with random material points, Adam steps, staged learning rates,
// reports, checkpoints and resume.
#include "nn/rom/rom_trainer.h"

#include <ATen/CPUGeneratorImpl.h>

#include <algorithm>
#include <chrono>
#include <optional>

#include "kernels/core/error.h"
#include "nn/io/unusable_file_error.h"
#include "nn/rom/adam.h"
#include "nn/rom/rom_checkpoint.h"
#include "nn/rom/rom_evaluation.h"
#include "nn/rom/rom_loss.h"

namespace romp::nn::rom {
namespace {

// The golden-ratio increment of splitmix64: consecutive epochs get well-separated generator seeds.
constexpr std::uint64_t kEpochSeedStride = 0x9E3779B97F4A7C15ull;

at::Generator epoch_generator(std::uint64_t seed, std::int64_t epoch) {
  return at::make_generator<at::CPUGeneratorImpl>(seed ^ (kEpochSeedStride * std::uint64_t(epoch + 1)));
}

void check_settings(const RomDataset& data, const TrainingSettings& s) {
  ROMP_CHECK(s.epochs >= 1 && s.batch >= 1 && s.points >= 1, "training needs epochs, batch and points >= 1");
  ROMP_CHECK(s.learning_rate > 0.0, "the learning rate must be positive");
  for (double fraction : s.decay_at)
    ROMP_CHECK(fraction > 0.0 && fraction < 1.0, "learning-rate decay points are fractions of the epochs in (0, 1)");
  const std::int64_t particles = data.particle_count();
  const std::int64_t expected = s.encoder_points == 0 ? particles : std::min(s.encoder_points, particles);
  ROMP_CHECK(data.encoder_indices.size(0) == expected,
             "the dataset was loaded for " + std::to_string(data.encoder_indices.size(0)) + " encoder points, the " +
                 "settings ask for " + std::to_string(expected));
}

// Everything the resumed run must share with the checkpoint's: data and settings.
void check_resumable(const std::string& path, const RomCheckpoint& checkpoint, const RomDataset& data,
                     const TrainingSettings& settings) {
  const TrainingRecord& record = checkpoint.model.training;
  std::vector<std::string> differences = settings.differences(record.settings);
  if (record.members != data.members || record.parameter_names != data.parameter_names)
    differences.push_back("the sweep's members differ");
  if (!torch::equal(checkpoint.model.encoder_indices.cpu(), data.encoder_indices.cpu()))
    differences.push_back("the encoder's points differ");
  if (differences.empty()) return;
  std::string list;
  for (const std::string& d : differences) list += "\n  " + d;
  throw io::UnusableFileError("checkpoint " + path +
                              " is from another training run; resume with the same sweep and options:" + list);
}

// Batch of the training snapshots `index` [B] with material points `points` [B, p] each.
LossBatch make_batch(const RomModel& model, const RomDataset& data, const torch::Tensor& encoder_inputs,
                     const torch::Tensor& index, const torch::Tensor& points) {
  const SnapshotSet& set = data.train;
  const std::int64_t count = index.size(0), per_snapshot = points.size(1);
  const torch::Tensor next = set.next.index_select(0, index);
  const torch::Tensor xhat_both = model.encoder->forward(encoder_inputs.index_select(0, torch::cat({index, next})));
  const torch::Tensor xhat = xhat_both.slice(0, 0, count);
  const torch::Tensor rate = (xhat_both.slice(0, count) - xhat) / set.dt.index_select(0, index).unsqueeze(1);
  const torch::Tensor rows = (index.unsqueeze(1) * data.particle_count() + points).flatten();
  LossBatch batch;
  batch.xhat = xhat.repeat_interleave(per_snapshot, 0);
  batch.xhat_rate = rate.repeat_interleave(per_snapshot, 0);
  batch.X = data.X.index_select(0, points.flatten());
  batch.x = set.x.view({-1, 3}).index_select(0, rows);
  batch.v = set.frame_velocity.view({-1, 3}).index_select(0, rows);
  batch.F = set.F.view({-1, 3, 3}).index_select(0, rows);
  batch.has_next = set.has_next.index_select(0, index).repeat_interleave(per_snapshot);
  return batch;
}

}  // namespace

TrainResult train_rom(const RomDataset& data, const TrainOptions& options,
                      const std::function<void(const EpochReport&)>& report,
                      const std::function<bool()>& stop_requested) {
  const TrainingSettings& settings = options.settings;
  check_settings(data, settings);
  ROMP_CHECK(!options.resume || !options.checkpoint.empty(), "resuming needs a checkpoint file");
  const auto start = std::chrono::steady_clock::now();
  const torch::Device device = data.X.device();

  TrainResult result;
  std::optional<Adam> adam;
  if (options.resume) {
    RomCheckpoint checkpoint = read_rom_checkpoint(options.checkpoint, device);
    check_resumable(options.checkpoint, checkpoint, data, settings);
    result.model = checkpoint.model;
    adam.emplace(result.model.parameters());
    adam->restore(checkpoint.adam_steps, checkpoint.first_moments, checkpoint.second_moments);
    result.resumed_at = result.model.training.epochs_done;
  } else {
    result.model = initial_model(data, settings);
    adam.emplace(result.model.parameters());
  }
  RomModel& model = result.model;

  const std::int64_t snapshots = data.train.size();
  const torch::Tensor encoder_inputs = data.train.x.index_select(1, model.encoder_indices);
  for (std::int64_t epoch = result.resumed_at; epoch < settings.epochs; ++epoch) {
    const auto epoch_start = std::chrono::steady_clock::now();
    const double learning_rate = settings.learning_rate_at(epoch);
    at::Generator generator = epoch_generator(settings.seed, epoch);
    const torch::Tensor order = torch::randperm(snapshots, generator, torch::kInt64);
    torch::Tensor sums = torch::zeros({4}, torch::TensorOptions(torch::kFloat64).device(device));
    std::int64_t batches = 0;
    for (std::int64_t begin = 0; begin < snapshots; begin += settings.batch, ++batches) {
      const torch::Tensor index = order.slice(0, begin, std::min(begin + settings.batch, snapshots));
      // Drawn on the CPU whatever the device, so both devices see the same batches.
      const torch::Tensor points =
          torch::randint(0, data.particle_count(), {index.size(0), settings.points}, generator, torch::kInt64);
      const LossTerms terms =
          rom_loss(*model.map, make_batch(model, data, encoder_inputs, index.to(device), points.to(device)),
                   settings.loss_weights, settings.derivatives);
      terms.total.backward();
      adam->step(learning_rate);
      sums += torch::stack({terms.total, terms.position, terms.F, terms.velocity}).detach().to(torch::kFloat64);
    }
    model.training.epochs_done = epoch + 1;
    const torch::Tensor epoch_means = (sums / double(batches)).cpu();  // waits for the device's queued work
    const double epoch_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - epoch_start).count();

    const bool stop = stop_requested && stop_requested();
    const bool last = epoch + 1 == settings.epochs;
    EpochReport line;
    line.checkpointed = !options.checkpoint.empty() && !last &&
                        (stop || (options.checkpoint_every > 0 && (epoch + 1) % options.checkpoint_every == 0));
    if (line.checkpointed) write_rom_checkpoint(options.checkpoint, model, *adam);
    const bool reported = epoch == result.resumed_at || last || stop ||
                          (options.report_every > 0 && (epoch + 1) % options.report_every == 0);
    if (reported && report) {
      line.epoch_seconds = epoch_seconds;
      line.epoch = epoch + 1;
      line.epochs = settings.epochs;
      line.started_at = result.resumed_at;
      line.learning_rate = learning_rate;
      line.loss = epoch_means[0].item<double>();
      line.position = epoch_means[1].item<double>();
      line.F = epoch_means[2].item<double>();
      line.velocity = epoch_means[3].item<double>();
      line.points = data.X.size(0);
      line.test_points = evaluated_points(line.points, options.report_points);
      if (data.test.size() > 0)
        line.test = reconstruction_errors(model, data.X, data.test, settings.derivatives, options.report_points);
      line.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      report(line);
    }
    if (stop && !last) {
      result.interrupted = true;
      return result;
    }
  }
  model.training.train_errors = reconstruction_errors(model, data.X, data.train, settings.derivatives);
  model.training.test_errors = reconstruction_errors(model, data.X, data.test, settings.derivatives);
  return result;
}

}  // namespace romp::nn::rom
