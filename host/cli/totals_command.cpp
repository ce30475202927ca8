// `romp totals`.
#include "host/cli/totals_command.h"

#include <fmt/format.h>

#include "host/cli/exit_codes.h"
#include "nn/io/snapshot_reader.h"
#include "nn/io/unusable_file_error.h"

namespace romp::cli {

CLI::App* add_totals_command(CLI::App& app, TotalsOptions& options) {
  CLI::App* totals = app.add_subcommand(
      "totals", "Per-frame kinetic, elastic, gravitational and total energy and linear and angular momentum, as CSV");
  totals->add_option("run", options.run, "Snapshot file (.h5) of a run (or RUN.h5.partial while it runs)")
      ->required()
      ->check(CLI::ExistingFile);
  return totals;
}

int totals_command(const TotalsOptions& options) {
  const io::SnapshotReader reader(options.run);
  fmt::print(
      "frame,time_s,step,kinetic_energy_J,elastic_energy_J,gravitational_energy_J,total_energy_J,"
      "momentum_x,momentum_y,momentum_z,angular_momentum_x,angular_momentum_y,angular_momentum_z\n");
  for (std::int64_t k = 0; k < reader.frame_count(); ++k) {
    const io::FrameData frame = reader.read_frame(k);
    if (!frame.totals)
      throw io::UnusableFileError(fmt::format(
          "{}: frame {} has no totals (written by a romp before they were, or at --output-points)", options.run, k));
    const io::FrameTotals& t = *frame.totals;
    const double total = t.kinetic_energy + t.elastic_energy + t.gravitational_energy;
    fmt::print("{},{:.9g},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n", k, frame.time,
               frame.step, t.kinetic_energy, t.elastic_energy, t.gravitational_energy, total, t.linear_momentum[0],
               t.linear_momentum[1], t.linear_momentum[2], t.angular_momentum[0], t.angular_momentum[1],
               t.angular_momentum[2]);
  }
  return kExitDone;
}

}  // namespace romp::cli
