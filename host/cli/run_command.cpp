// `romp run`.
#include "host/cli/run_command.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <map>
#include <string>

#include "host/cli/compare_command.h"
#include "host/cli/exit_codes.h"
#include "host/run/interrupt.h"
#include "host/run/stage_table.h"
#include "host/scene/scene_parser.h"

namespace romp::cli {

CLI::App* add_run_command(CLI::App& app, RunCommandOptions& options, const std::string& default_scene) {
  CLI::App* command = app.add_subcommand("run", "Run a scene and write its snapshots");
  options.scene.path = default_scene;
  command->add_option("scene", options.scene.path, "Scene file (TOML); default: the quick start's scene")
      ->check(CLI::ExistingFile);
  command->add_option("-o,--output", options.run.output, "Snapshot file (.h5), instead of the scene's [output] file");
  command->add_flag("--resume", options.run.resume, "Continue an interrupted run from its last complete frame");
  command->add_flag("--deterministic", options.deterministic, "Bitwise reproducible (CPU, one thread)");
  command->add_flag("--ply", options.run.ply, "Also write a PLY point cloud per frame");
  command->add_flag("!--no-progress", options.run.progress, "No progress bar");
  CLI::Option* output_points =
      command
          ->add_option("--output-points", options.run.output_points,
                       "Write the frames at the material points of this snapshot (e.g. a finer sampling of the same "
                       "body) instead of the scene's: decoded by the map with --rom (super-resolution), carried as "
                       "tracers otherwise (x and v; see --tracers-by)")
          ->check(CLI::ExistingFile)
          ->excludes("--resume");
  add_set_option(*command, options.scene);
  add_law_option(*command, options.scene);
  run::add_reduced_run_options(*command, options.reduced);
  command
      ->add_option("--tracers-by", options.run.tracers_by,
                   "What carries the --output-points tracers of a full-order run: material (the particle domain "
                   "that holds a point, where the scene has domains, else the grid) or grid (the grid's velocity "
                   "everywhere: the ROM paper's tracer-particle technique, blind to enriched corners)")
      ->transform(CLI::CheckedTransformer(
                      std::map<std::string, engine::TracerCarrier>{{"material", engine::TracerCarrier::Material},
                                                                   {"grid", engine::TracerCarrier::Grid}})
                      .description(""))
      ->type_name("{material,grid}")
      ->needs(output_points)
      ->excludes("--rom");
  command
      ->add_option("--compare", options.reference,
                   "Then print the run's position error against this reference run of the same scene (as compare)")
      ->check(CLI::ExistingFile);
  command->add_flag("--frames", options.per_frame, "With --compare: also print the error of every frame");
  return command;
}

int run_command(DeviceChoice choice, int threads, RunCommandOptions options) {
  if (options.deterministic) {
    // The CPU path with one thread sums every grid node's contributions in one fixed order.
    if (choice == DeviceChoice::Cuda)
      throw CLI::ValidationError("--deterministic", "bitwise reproducibility is provided on the CPU only");
    choice = DeviceChoice::Cpu;
    threads = 1;
  }
  const scene::Scene scene =
      scene::load_scene(options.scene.path, options.scene.overrides(), options.scene.learned_laws());
  if (!options.reduced.model.empty())
    options.run.make_reduced = [reduced = options.reduced](const Exec& exec, const scene::SceneSetup& setup) {
      return run::make_reduced_simulation(reduced, exec, setup);
    };
  options.run.frame_graphs = !options.reduced.no_frame_graphs;
  const Exec exec = select_backend(choice, threads);
  const run::RunResult r = run::run_scene(exec, scene, options.run);
  if (r.interrupted) {
    spdlog::warn("interrupted after frame {}; {} holds the frames so far{}", r.last_frame, r.output_in_progress,
                 options.run.make_reduced ? "" : "; continue with --resume");
    return run::kExitInterrupted;
  }
  // The file holds frame 0, the initial state, besides the frames simulated (by this process, or before
  // a resume).
  fmt::print(
      "{}: {} particles, {} frames simulated ({} in the file, frame 0 the initial state), {} substeps ({:.4g} s "
      "simulated) in {:.3f} s on {}\n",
      scene.name, r.particles, r.frames_written, r.last_frame + 1, r.substeps, r.simulated_seconds, r.wall_seconds,
      to_string(exec.backend));
  for (const std::string& line : r.diagnostics) fmt::print("{}\n", line);
  fmt::print("output: {}\n\n{}", r.output, run::stage_table(r.stage_seconds));
  if (options.reference.empty()) return kExitDone;
  fmt::print("\n");
  return compare_command({r.output, options.reference, options.per_frame, 0});
}

}  // namespace romp::cli
