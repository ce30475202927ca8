// `romp train-rom DIR -o model.h5`: the ROM's offline stage from the command line. Loads a sweep folder, trains
// the deformation map and encoder (nn/rom), prints a progress line with the losses and test errors, checkpoints
// for --resume (and on Ctrl-C), and writes the model file.
#pragma once

#include <cstdint>
#include <string>

#include "host/backend_selection.h"
#include "nn/rom/rom_model.h"

namespace CLI {
class App;
}

namespace romp::cli {

struct TrainRomOptions {
  std::string sweep_dir;
  std::string output;  // the model file; its checkpoint is "<output>.checkpoint"
  nn::rom::TrainingSettings settings;
  bool resume = false;
  std::int64_t checkpoint_every = 50;
  std::int64_t report_every = 10;
};

// Registers the subcommand and its options, which fill `options` when parsed.
CLI::App* add_train_rom_command(CLI::App& app, TrainRomOptions& options);

// Runs it; returns the exit code (README "Exit codes": 0 done, 3 unusable sweep folder or --resume without a
// checkpoint, 130 interrupted with a checkpoint to --resume from). Other failures, a checkpoint of other settings
// among them, throw romp::Error.
int train_rom_command(DeviceChoice choice, int threads, const TrainRomOptions& options);

}  // namespace romp::cli
