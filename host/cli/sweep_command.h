// `romp sweep SCENE -o FOLDER`: runs every member of a scene's [sweep], each as its own `romp run`.
#pragma once

#include <CLI/CLI.hpp>

#include "host/cli/global_options.h"
#include "host/cli/scene_arguments.h"
#include "host/run/sweep_runner.h"

namespace romp::cli {

struct SweepCommandOptions {
  SceneArguments scene;  // the path and --law (a sweep's members declare their own parameters)
  run::SweepOptions sweep;
};

CLI::App* add_sweep_command(CLI::App& app, SweepCommandOptions& options);

// Runs the members this process is assigned, passing `global` on to each member's run. Returns the exit
// code: 0, or kExitSweepMembersFailed when a member failed.
int sweep_command(const GlobalOptions& global, SweepCommandOptions options);

}  // namespace romp::cli
