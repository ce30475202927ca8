// --set and --law: parsed into what scene::load_scene takes.
#include "host/cli/scene_arguments.h"

#include "host/scene/expression.h"
#include "kernels/core/error.h"

namespace romp::cli {

scene::ParameterValues SceneArguments::overrides() const {
  try {
    return scene::parse_assignments(sets);
  } catch (const Error& error) {
    throw CLI::ValidationError("--set", error.what());
  }
}

scene::LearnedLaws SceneArguments::learned_laws() const {
  scene::LearnedLaws learned;
  for (const std::string& a : laws) {
    const std::size_t equals = a.find('=');
    if (equals == 0 || equals == std::string::npos || equals + 1 == a.size())
      throw CLI::ValidationError("--law", "expected MATERIAL=law.h5, got '" + a + "'");
    if (!learned.emplace(a.substr(0, equals), a.substr(equals + 1)).second)
      throw CLI::ValidationError("--law", "material '" + a.substr(0, equals) + "' is given twice");
  }
  return learned;
}

void add_set_option(CLI::App& command, SceneArguments& scene) {
  command.add_option("--set", scene.sets, "Override a declared parameter: name=value (repeatable)");
}

void add_law_option(CLI::App& command, SceneArguments& scene) {
  command.add_option("--law", scene.laws, "Run material NAME with a learned law instead: NAME=law.h5 (repeatable)");
}

}  // namespace romp::cli
