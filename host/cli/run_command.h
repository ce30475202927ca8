// `romp run [SCENE]`: runs a scene (full order, or reduced with --rom) and writes its snapshots, then a
// table of where the time went.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

#include "host/backend_selection.h"
#include "host/cli/scene_arguments.h"
#include "host/run/reduced_run_options.h"
#include "host/run/scene_runner.h"

namespace romp::cli {

struct RunCommandOptions {
  SceneArguments scene;  // the path defaults to the quick start's scene
  run::RunOptions run;
  run::ReducedRunOptions reduced;
  bool deterministic = false;  // bitwise reproducible: the CPU, one thread
  std::string reference;       // --compare: then the position error against this run
  bool per_frame = false;      // with --compare: every frame's error too
};

// `default_scene`: the scene run when none is named.
CLI::App* add_run_command(CLI::App& app, RunCommandOptions& options, const std::string& default_scene);

// Runs on `choice` with `threads` CPU threads. Returns the exit code: 0, or run::kExitInterrupted.
int run_command(DeviceChoice choice, int threads, RunCommandOptions options);

}  // namespace romp::cli
