// `romp compare RUN REFERENCE`: the position error (%) of a run against a reference run of the same
// scene (ROM paper), also printed by `romp run --compare`.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace romp::cli {

struct CompareOptions {
  std::string run, reference;     // snapshot files
  bool per_frame = false;         // also every frame's error
  std::int64_t first_frames = 0;  // > 0: frames 0 .. N-1 only
};

CLI::App* add_compare_command(CLI::App& app, CompareOptions& options);

// Prints the comparison. Returns the exit code (0).
int compare_command(const CompareOptions& options);

}  // namespace romp::cli
