// Offline training of the ROM (paper Sec. 4, App. B): g and e together by Adam on Eq. (31) over mini-batches of
// snapshots, with the learning rate in stages, reports with test-set errors, checkpoints and an exact resume.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "nn/rom/rom_dataset.h"
#include "nn/rom/rom_model.h"

namespace romp::nn::rom {

struct TrainOptions {
  TrainingSettings settings;
  std::int64_t report_every = 10;  // epochs between reports (there is also one after the first and the last)
  // Material points per test snapshot a report compares (evenly spaced; 0: all). The record written at the
  // end always compares every point.
  std::int64_t report_points = 256;
  std::string checkpoint;              // checkpoint file; empty: none
  std::int64_t checkpoint_every = 50;  // epochs between checkpoints (and one when stopped on request)
  bool resume = false;                 // continue from `checkpoint`, which must be from the same data and settings
};

struct EpochReport {
  std::int64_t epoch = 0, epochs = 0;  // epochs done, of all
  std::int64_t started_at = 0;         // epochs done when this call started (a resumed run's checkpoint)
  double learning_rate = 0.0;
  double loss = 0.0, position = 0.0, F = 0.0, velocity = 0.0;  // means over the epoch's batches: Eq. (31), its terms
  double seconds = 0.0;                                        // since this call started
  double epoch_seconds = 0.0;                // this epoch's mini-batches alone (no evaluation or checkpoint)
  std::optional<ReconstructionErrors> test;  // when the sweep has test members
  std::int64_t test_points = 0, points = 0;  // material points per snapshot compared for `test`, of all
  bool checkpointed = false;
};

struct TrainResult {
  RomModel model;               // epochs_done, and the train and test errors once finished
  std::int64_t resumed_at = 0;  // epochs the checkpoint had done; 0 for a fresh start
  bool interrupted = false;     // stopped on request after epochs_done epochs, checkpoint written
};

// `data` must have been loaded with settings.encoder_points and settings.seed. Deterministic for a fixed seed on
// one device and thread count: every epoch draws its batch order and material points from its own generator
// seeded by (seed, epoch), so a resumed run repeats the uninterrupted one bitwise. `stop_requested` is asked
// after every epoch.
TrainResult train_rom(const RomDataset& data, const TrainOptions& options,
                      const std::function<void(const EpochReport&)>& report = {},
                      const std::function<bool()>& stop_requested = {});

}  // namespace romp::nn::rom
