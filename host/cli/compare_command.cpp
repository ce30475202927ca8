// `romp compare`.
#include "host/cli/compare_command.h"

#include <fmt/format.h>

#include "host/cli/exit_codes.h"
#include "host/run/position_error.h"

namespace romp::cli {

CLI::App* add_compare_command(CLI::App& app, CompareOptions& options) {
  CLI::App* compare = app.add_subcommand(
      "compare", "Position error (%) of a run against a reference run of the same scene (ROM paper)");
  compare->add_option("run", options.run, "Snapshot file (.h5) of the run to measure")
      ->required()
      ->check(CLI::ExistingFile);
  compare->add_option("reference", options.reference, "Snapshot file (.h5) of the reference (full-order) run")
      ->required()
      ->check(CLI::ExistingFile);
  compare->add_flag("--frames", options.per_frame, "Also print the error of every frame");
  compare
      ->add_option("--first-frames", options.first_frames,
                   "Compare frames 0 .. N-1 only (e.g. what a run that stopped wrote, RUN.h5.partial)")
      ->check(CLI::PositiveNumber);
  return compare;
}

int compare_command(const CompareOptions& options) {
  const run::PositionError error = run::compare_snapshots(options.run, options.reference, options.first_frames);
  if (options.per_frame) {
    fmt::print("{:>6}  {:>12}  {:>16}  {:>16}\n", "frame", "time (s)", "position error %", "MSE (m^2)");
    for (std::size_t k = 0; k < error.frame_percent.size(); ++k)
      fmt::print("{:>6}  {:>12.6g}  {:>16.6g}  {:>16.6g}\n", k, error.frame_times[k], error.frame_percent[k],
                 error.frame_mse[k]);
  }
  fmt::print(
      "{} against {}: accumulated position error {:.6g}% over {} frames of {} material points; "
      "mean position MSE over frames after the first {:.6g} m^2\n",
      options.run, options.reference, error.percent, error.frame_percent.size(), error.particles, error.mean_mse);
  return kExitDone;
}

}  // namespace romp::cli
