// The romp command line: one entry point for every mode. Exit codes (README "Exit codes"):
// 0 done, 1 run failed, 2 bad arguments, 3 invalid scene or input file, 4 simulation went
// non-finite, 5 sweep members failed, 130 interrupted (resumable with --resume).
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <exception>
#include <string>
#include <vector>

#include "host/backend_selection.h"
#include "host/build_info.h"
#include "host/info_report.h"
#include "host/run/interrupt.h"
#include "host/run/position_error.h"
#include "host/run/reduced_run_options.h"
#include "host/learn_law_command.h"
#include "host/run/scene_runner.h"
#include "host/run/stage_table.h"
#include "host/run/sweep_runner.h"
#include "host/scene/scene_parser.h"
#include "host/scene/scene_setup.h"
#include "host/scene/toml_reader.h"
#include "host/train_rom_command.h"
#include "kernels/core/device.h"
#include "kernels/core/error.h"
#include "nn/torch_info.h"

namespace {

constexpr int kExitRunFailed = 1;
constexpr int kExitBadArguments = 2;
constexpr int kExitInvalidInput = 3;
constexpr int kExitNonFinite = 4;
constexpr int kExitSweepMembersFailed = 5;

// "--set name=value" pairs as parameter overrides.
romp::scene::ParameterValues parse_overrides(const std::vector<std::string>& sets) {
  try {
    return romp::scene::parse_assignments(sets);
  } catch (const romp::Error& error) {
    throw CLI::ValidationError("--set", error.what());
  }
}

// NAME=FILE assignments of --law.
romp::scene::LearnedLaws parse_laws(const std::vector<std::string>& assignments) {
  romp::scene::LearnedLaws laws;
  for (const std::string& a : assignments) {
    const std::size_t equals = a.find('=');
    if (equals == 0 || equals == std::string::npos || equals + 1 == a.size())
      throw CLI::ValidationError("--law", "expected MATERIAL=law.h5, got '" + a + "'");
    if (!laws.emplace(a.substr(0, equals), a.substr(equals + 1)).second)
      throw CLI::ValidationError("--law", "material '" + a.substr(0, equals) + "' is given twice");
  }
  return laws;
}

int check_scene(const std::string& path, const romp::scene::ParameterValues& overrides,
                const romp::scene::LearnedLaws& laws) {
  const romp::scene::Scene scene = romp::scene::load_scene(path, overrides, laws);
  const romp::scene::SceneSetup setup = romp::scene::build_scene(scene);
  fmt::print("{}", scene.resolved_text);
  std::string counts;
  for (std::size_t i = 0; i < scene.objects.size(); ++i)
    counts += fmt::format("{}{} {}", i ? ", " : "", scene.objects[i].name, setup.particles_per_object[i]);
  spdlog::info("{}: valid; {} particles ({}), {} frames to t = {} s", path, setup.particles.count(), counts,
               scene.frame_count, scene.end_time);
  if (scene.sweep)
    spdlog::info("{}: sweep of {} members", path, romp::scene::sweep_members(*scene.sweep).size());
  return 0;
}

int compare(const std::string& run, const std::string& reference, bool per_frame, std::int64_t first_frames = 0) {
  const romp::run::PositionError error = romp::run::compare_snapshots(run, reference, first_frames);
  if (per_frame) {
    fmt::print("{:>6}  {:>12}  {:>16}  {:>16}\n", "frame", "time (s)", "position error %", "MSE (m^2)");
    for (std::size_t k = 0; k < error.frame_percent.size(); ++k)
      fmt::print("{:>6}  {:>12.6g}  {:>16.6g}  {:>16.6g}\n", k, error.frame_times[k], error.frame_percent[k],
                 error.frame_mse[k]);
  }
  fmt::print("{} against {}: accumulated position error {:.6g}% over {} frames of {} material points; "
             "mean position MSE over frames after the first {:.6g} m^2\n",
             run, reference, error.percent, error.frame_percent.size(), error.particles, error.mean_mse);
  return 0;
}

int run_scene(romp::DeviceChoice choice, int threads, const std::string& path,
              const romp::scene::ParameterValues& overrides, const romp::scene::LearnedLaws& laws,
              const romp::run::RunOptions& options, bool deterministic, const std::string& reference,
              bool per_frame) {
  if (deterministic) {
    // The CPU path with one thread sums every grid node's contributions in one fixed order.
    if (choice == romp::DeviceChoice::Cuda)
      throw CLI::ValidationError("--deterministic", "bitwise reproducibility is provided on the CPU only");
    choice = romp::DeviceChoice::Cpu;
    threads = 1;
  }
  const romp::scene::Scene scene = romp::scene::load_scene(path, overrides, laws);
  const romp::Exec exec = romp::select_backend(choice, threads);
  const romp::run::RunResult r = romp::run::run_scene(exec, scene, options);
  if (r.interrupted) {
    spdlog::warn("interrupted after frame {}; {} holds the frames so far{}", r.last_frame, r.output_in_progress,
                 options.make_reduced ? "" : "; continue with --resume");
    return romp::run::kExitInterrupted;
  }
  fmt::print("{}: {} particles, {} frames, {} substeps ({:.4g} s simulated) in {:.3f} s on {}\n", scene.name,
             r.particles, r.frames_written, r.substeps, r.simulated_seconds, r.wall_seconds,
             romp::to_string(exec.backend));
  for (const std::string& line : r.diagnostics) fmt::print("{}\n", line);
  fmt::print("output: {}\n\n{}", r.output, romp::run::stage_table(r.stage_seconds));
  if (!reference.empty()) {
    fmt::print("\n");
    return compare(r.output, reference, per_frame);
  }
  return 0;
}

int sweep(const std::string& path, const romp::run::SweepOptions& options) {
  const romp::run::SweepSummary s = romp::run::run_sweep(path, options);
  fmt::print("sweep {}: {} members; rank {}/{} was assigned {}: {} already finished, {} run now, {} claimed by "
             "another process, {} failed\n",
             path, s.members, s.rank, s.ranks, s.assigned, s.finished_before, s.ran, s.busy_elsewhere,
             s.failed.size());
  for (const std::string& failure : s.failed) fmt::print("  {}\n", failure);
  return s.failed.empty() ? 0 : kExitSweepMembersFailed;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"romp: material point method with neural reduced-order models"};
  app.require_subcommand(1);
  std::string device = "auto";
  int threads = 0;
  std::string log_level = "info";
  app.add_option("--device", device, "Backend: auto (CUDA if a device answers), cpu or cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  app.add_option("--threads", threads, "CPU threads (0 = OpenMP default)")->check(CLI::NonNegativeNumber);
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}));

  app.add_subcommand("info", "Version, commit, build configuration and the devices found");

  std::string scene_path = ROMP_DEFAULT_SCENE;
  std::vector<std::string> sets;
  CLI::App* check = app.add_subcommand("check", "Validate a scene and print it resolved, every default filled in");
  check->add_option("scene", scene_path, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
  check->add_option("--set", sets, "Override a declared parameter: name=value (repeatable)");
  std::vector<std::string> law_assignments;
  const char* law_help = "Run material NAME with a learned law instead: NAME=law.h5 (repeatable)";
  check->add_option("--law", law_assignments, law_help);

  CLI::App* run = app.add_subcommand("run", "Run a scene and write its snapshots");
  romp::run::RunOptions run_options;
  bool deterministic = false;
  run->add_option("scene", scene_path, "Scene file (TOML); default: the quick start's scene")
      ->check(CLI::ExistingFile);
  run->add_option("-o,--output", run_options.output, "Snapshot file (.h5), instead of the scene's [output] file");
  run->add_flag("--resume", run_options.resume, "Continue an interrupted run from its last complete frame");
  run->add_flag("--deterministic", deterministic, "Bitwise reproducible (CPU, one thread)");
  run->add_flag("--ply", run_options.ply, "Also write a PLY point cloud per frame");
  run->add_flag("!--no-progress", run_options.progress, "No progress bar");
  run->add_option("--output-points", run_options.output_points,
                  "Write the frames at the material points of this snapshot (e.g. a finer sampling of the same "
                  "body) instead of the scene's: decoded by the map with --rom (super-resolution), carried as "
                  "tracers otherwise (x and v; in particle domains where the scene has them, else by the grid)")
      ->check(CLI::ExistingFile)
      ->excludes("--resume");
  run->add_option("--set", sets, "Override a declared parameter: name=value (repeatable)");
  run->add_option("--law", law_assignments, law_help);
  romp::run::ReducedRunOptions reduced_options;
  romp::run::add_reduced_run_options(*run, reduced_options);
  std::string run_reference;
  bool per_frame = false;
  run->add_option("--compare", run_reference,
                  "Then print the run's position error against this reference run of the same scene (as compare)")
      ->check(CLI::ExistingFile);
  run->add_flag("--frames", per_frame, "With --compare: also print the error of every frame");

  CLI::App* sweep_command = app.add_subcommand("sweep", "Run every member of a scene's [sweep]");
  romp::run::SweepOptions sweep_options;
  sweep_command->add_option("scene", scene_path, "Scene file with a [sweep] table")->required()->check(
      CLI::ExistingFile);
  sweep_command->add_option("-o,--output", sweep_options.output_dir, "Output folder")->required();
  sweep_command->add_option("-j,--jobs", sweep_options.jobs, "Members run at once on this machine")
      ->check(CLI::PositiveNumber);
  sweep_command->add_option("--law", law_assignments, law_help);

  CLI::App* compare_command =
      app.add_subcommand("compare", "Position error (%) of a run against a reference run of the same scene (ROM paper)");
  std::string compared_run, reference_run;
  compare_command->add_option("run", compared_run, "Snapshot file (.h5) of the run to measure")->required()->check(
      CLI::ExistingFile);
  compare_command->add_option("reference", reference_run, "Snapshot file (.h5) of the reference (full-order) run")
      ->required()
      ->check(CLI::ExistingFile);
  compare_command->add_flag("--frames", per_frame, "Also print the error of every frame");
  std::int64_t first_frames = 0;
  compare_command
      ->add_option("--first-frames", first_frames,
                   "Compare frames 0 .. N-1 only (e.g. what a run that stopped wrote, RUN.h5.partial)")
      ->check(CLI::PositiveNumber);
  romp::LearnLawOptions learn_law_options;
  CLI::App* learn_law = romp::add_learn_law_command(app, learn_law_options);
  romp::TrainRomOptions train_rom_options;
  romp::add_train_rom_command(app, train_rom_options);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int code = app.exit(error);
    return code == 0 ? 0 : kExitBadArguments;
  }
  spdlog::set_level(spdlog::level::from_str(log_level));

  try {
    const romp::DeviceChoice choice = romp::parse_device_choice(device);
    if (app.got_subcommand("info")) {
      fmt::print("{}", romp::info_report(romp::build_info(), romp::probe_cuda(), romp::nn::torch_info()));
      return 0;
    }
    if (app.got_subcommand("compare")) return compare(compared_run, reference_run, per_frame, first_frames);
    if (app.got_subcommand("sweep")) {
      sweep_options.run_arguments = {"--device", device, "--threads", std::to_string(threads), "--log-level", log_level};
      sweep_options.laws = parse_laws(law_assignments);
      return sweep(scene_path, sweep_options);
    }
    if (learn_law->parsed()) return romp::learn_law(choice, threads, learn_law_options);
    if (app.got_subcommand("train-rom")) return romp::train_rom_command(choice, threads, train_rom_options);
    const romp::scene::ParameterValues overrides = parse_overrides(sets);
    const romp::scene::LearnedLaws laws = parse_laws(law_assignments);
    if (app.got_subcommand("check")) return check_scene(scene_path, overrides, laws);
    if (!reduced_options.model.empty())
      run_options.make_reduced = [&reduced_options](const romp::Exec& exec, const romp::scene::SceneSetup& setup) {
        return romp::run::make_reduced_simulation(reduced_options, exec, setup);
      };
    return run_scene(choice, threads, scene_path, overrides, laws, run_options, deterministic, run_reference,
                     per_frame);
  } catch (const CLI::ParseError& error) {
    return app.exit(error) == 0 ? 0 : kExitBadArguments;
  } catch (const romp::scene::SceneError& error) {
    spdlog::error("{}", error.what());
    return kExitInvalidInput;
  } catch (const romp::NonFiniteError& error) {
    spdlog::error("{}", error.what());
    return kExitNonFinite;
  } catch (const std::exception& error) {
    spdlog::error("{}", error.what());
    return kExitRunFailed;
  }
}
