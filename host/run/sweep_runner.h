// `romp sweep`: every member of a scene's [sweep] as its own `romp run` child process, a manifest
// describing them, resumable (finished members are skipped) and shared across MPI ranks.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host/scene/scene_parser.h"

namespace romp::run {

struct SweepOptions {
  std::string output_dir;
  int jobs = 1;                            // child processes at once on this machine
  std::vector<std::string> run_arguments;  // global options passed to each child (device, threads, ...)
  std::string executable;                  // the romp binary for the children (default: this process's)
  scene::LearnedLaws laws;  // materials every member runs with a learned law instead (scene::parse_scene)
  // Declared parameters set for every member (romp sweep --set), e.g. a coarser dx to shrink a paper's
  // sweep; a swept parameter cannot be set.
  scene::ParameterValues overrides;
};

struct SweepSummary {
  std::int64_t members = 0;   // in the whole sweep
  std::int64_t assigned = 0;  // to this rank
  std::int64_t finished_before = 0, ran = 0, busy_elsewhere = 0;
  std::vector<std::string> failed;  // "member 3: exit code 4, log DIR/logs/member_000003.log"
  int rank = 0, ranks = 1;
};

// File names inside the output folder, shared with readers of sweeps.
std::string member_stem(std::int64_t index);  // "member_000003"

SweepSummary run_sweep(const std::string& scene_path, const SweepOptions& options);

}  // namespace romp::run
