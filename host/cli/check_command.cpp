// `romp check`.
#include "host/cli/check_command.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <string>

#include "host/cli/exit_codes.h"
#include "host/scene/scene_setup.h"
#include "host/scene/sweep.h"

namespace romp::cli {

CLI::App* add_check_command(CLI::App& app, CheckOptions& options) {
  CLI::App* check = app.add_subcommand("check", "Validate a scene and print it resolved, every default filled in");
  check->add_option("scene", options.scene.path, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
  add_set_option(*check, options.scene);
  add_law_option(*check, options.scene);
  return check;
}

int check_command(const CheckOptions& options) {
  const std::string& path = options.scene.path;
  const scene::Scene scene = scene::load_scene(path, options.scene.overrides(), options.scene.learned_laws());
  const scene::SceneSetup setup = scene::sample_scene(scene);  // no engine: no law is loaded
  fmt::print("{}", scene.resolved_text);
  std::string counts;
  for (std::size_t i = 0; i < scene.objects.size(); ++i)
    counts += fmt::format("{}{} {}", i ? ", " : "", scene.objects[i].name, setup.particles_per_object[i]);
  spdlog::info("{}: valid; {} particles ({}), {} frames to t = {} s", path, setup.particles.count(), counts,
               scene.frame_count, scene.end_time);
  if (scene.sweep) spdlog::info("{}: sweep of {} members", path, scene::sweep_members(*scene.sweep).size());
  return kExitDone;
}

}  // namespace romp::cli
