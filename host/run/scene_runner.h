// run_scene: a run of a scene (full-order, or reduced-order with a model), frame by frame, with snapshots written off
// the critical path, a checkpoint per frame for --resume, a progress bar, and a stage table.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "host/run/simulation.h"
#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"
#include "kernels/core/exec.h"

namespace romp::run {

struct RunOptions {
  std::string output;   // snapshot path; empty: the scene's [output] file
  bool resume = false;  // continue from the checkpoint of an unfinished run of the same scene
  bool ply = false;     // PLY per frame even if the scene does not ask for it
  bool progress = true;
  std::int64_t stop_at_frame = -1;  // >= 0: stop after this frame, leaving a resumable partial output
  // A snapshot whose material points (/particles) the frames are written at instead of the scene's:
  // decoded by the map in a reduced-order run, carried as tracers in a full-order one (Simulation::
  // track_points). Empty: the scene's material points.
  std::string output_points;
  // What carries output_points in a full-order run with particle domains (engine::TracerCarrier).
  engine::TracerCarrier tracers_by = engine::TracerCarrier::Material;
  // Set for a reduced-order run: builds its simulation from the scene's setup (the model it needs is
  // the caller's business). Empty: the full-order engine.
  std::function<std::unique_ptr<Simulation>(const Exec&, const scene::SceneSetup&)> make_reduced;
  // false: full-order batches of substeps launched, never replayed as CUDA graphs (engine::GraphReplay::Never).
  bool frame_graphs = true;
};

struct RunResult {
  std::string output;              // the finished snapshot ("" when the run stopped early)
  std::string output_in_progress;  // the partial snapshot of a run that stopped early
  Index particles = 0;
  std::int64_t first_frame = 0;     // the frame this process started from (> 0 when resumed)
  std::int64_t last_frame = 0;      // the last frame written
  std::int64_t frames_written = 0;  // by this process
  std::int64_t substeps = 0;        // by this process
  double simulated_seconds = 0.0, wall_seconds = 0.0;
  bool interrupted = false;  // stopped by a signal or stop_at_frame; resumable
  std::vector<std::pair<std::string, double>> stage_seconds;
  std::vector<std::string> diagnostics;  // the simulation's solver-health lines
};

// Throws scene::SceneError for unusable input, NonFiniteError (with the frames written so far
// readable in the partial snapshot) when the simulation blows up, romp::Error otherwise.
RunResult run_scene(const Exec& exec, const scene::Scene& scene, const RunOptions& options);

}  // namespace romp::run
