// A scene as check, run and sweep take it: the file, parameter overrides (--set) and learned laws in
// place of named materials (--law).
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "host/scene/scene_parser.h"

namespace romp::cli {

struct SceneArguments {
  std::string path;
  std::vector<std::string> sets;  // name=value
  std::vector<std::string> laws;  // MATERIAL=law.h5

  // The --set pairs as parameter overrides; a malformed one is a CLI::ValidationError (exit 2).
  scene::ParameterValues overrides() const;
  // The --law pairs; a malformed or repeated one is a CLI::ValidationError (exit 2).
  scene::LearnedLaws learned_laws() const;
};

// Declares --set on `command`.
void add_set_option(CLI::App& command, SceneArguments& scene);
// Declares --law on `command`.
void add_law_option(CLI::App& command, SceneArguments& scene);

}  // namespace romp::cli
