// `romp learn-law TRAJ.h5 -o law.h5`: trains neural elastic and plastic laws on a ground-truth snapshot.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

#include "host/backend_selection.h"

namespace romp::cli {

struct LearnLawOptions {
  std::string trajectory;  // a `romp run` snapshot with one frame per substep
  std::string output;      // the law file; its checkpoint is <output>.checkpoint
  int64_t epochs = 300;
  int64_t steps = 1000;
  int64_t checkpoint_every = 0;
  uint64_t seed = 0;
  bool resume = false;
  // The teacher-forcing period's cosine schedule (substeps) and the velocity penalty: nn::nclaw::TrainingOptions.
  int64_t teacher_forcing_first = 25, teacher_forcing_last = 200;
  double velocity_weight = 0.0;
  // "motion" (the method), or an oracle of host/nclaw/oracles.h: "labeled" writes a law file,
  // "system-identification" a scene material table (.toml) with the identified E and ν.
  std::string method = "motion";
  int64_t pair_stride = 10;                            // labeled: constitutive pairs from every this many frames
  double initial_youngs = 3e4, initial_poisson = 0.3;  // system-identification: the starting guess
};

// Declares the subcommand and its options on `app`.
CLI::App* add_learn_law_command(CLI::App& app, LearnLawOptions& options);

// Trains, logging every epoch's loss; checkpoints after every epoch and removes the checkpoint when
// the law file is written. Returns the process exit code (0).
int learn_law_command(DeviceChoice choice, int threads, const LearnLawOptions& options);

}  // namespace romp::cli
