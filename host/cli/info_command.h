// `romp info`: version, commit, build configuration and the devices found.
#pragma once

#include <CLI/CLI.hpp>

namespace romp::cli {

CLI::App* add_info_command(CLI::App& app);

// Prints the report (info_report.h). Returns the exit code (0).
int info_command();

}  // namespace romp::cli
