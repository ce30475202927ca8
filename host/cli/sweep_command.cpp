// `romp sweep`.
#include "host/cli/sweep_command.h"

#include <fmt/format.h>

#include <string>

#include "host/cli/exit_codes.h"

namespace romp::cli {

CLI::App* add_sweep_command(CLI::App& app, SweepCommandOptions& options) {
  CLI::App* sweep = app.add_subcommand("sweep", "Run every member of a scene's [sweep]");
  sweep->add_option("scene", options.scene.path, "Scene file with a [sweep] table")
      ->required()
      ->check(CLI::ExistingFile);
  sweep->add_option("-o,--output", options.sweep.output_dir, "Output folder")->required();
  sweep->add_option("-j,--jobs", options.sweep.jobs, "Members run at once on this machine")->check(CLI::PositiveNumber);
  add_set_option(*sweep, options.scene);
  add_law_option(*sweep, options.scene);
  return sweep;
}

int sweep_command(const GlobalOptions& global, SweepCommandOptions options) {
  options.sweep.run_arguments = {"--device",    global.device,   "--threads", std::to_string(global.threads),
                                 "--log-level", global.log_level};
  options.sweep.laws = options.scene.learned_laws();
  options.sweep.overrides = options.scene.overrides();
  const std::string& path = options.scene.path;
  const run::SweepSummary s = run::run_sweep(path, options.sweep);
  fmt::print(
      "sweep {}: {} members; rank {}/{} was assigned {}: {} already finished, {} run now, {} claimed by "
      "another process, {} failed\n",
      path, s.members, s.rank, s.ranks, s.assigned, s.finished_before, s.ran, s.busy_elsewhere, s.failed.size());
  for (const std::string& failure : s.failed) fmt::print("  {}\n", failure);
  return s.failed.empty() ? kExitDone : kExitSweepMembersFailed;
}

}  // namespace romp::cli
