// `romp totals RUN.h5`: the energies and momenta a run wrote with each frame, as CSV (no h5py needed).
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace romp::cli {

struct TotalsOptions {
  std::string run;  // snapshot file
};

CLI::App* add_totals_command(CLI::App& app, TotalsOptions& options);

// Prints one CSV line per frame. Returns the exit code (0); a snapshot without totals (written by an
// older romp, or at --output-points) is an unusable input.
int totals_command(const TotalsOptions& options);

}  // namespace romp::cli
