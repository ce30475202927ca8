// `romp check SCENE`: validates a scene, samples its objects and prints it resolved, every default
// filled in. Runs no simulation and no network (a learned law is checked to be a law file).
#pragma once

#include <CLI/CLI.hpp>

#include "host/cli/scene_arguments.h"

namespace romp::cli {

struct CheckOptions {
  SceneArguments scene;
};

CLI::App* add_check_command(CLI::App& app, CheckOptions& options);

// Returns the exit code (0); an invalid scene throws scene::SceneError.
int check_command(const CheckOptions& options);

}  // namespace romp::cli
