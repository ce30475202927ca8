// `romp run --rom model.h5 ...`: the command-line options of a reduced-order run and the factory that
// builds its simulation from a scene's setup.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <memory>
#include <string>

#include "host/engine/reduced_sim.h"
#include "host/run/simulation.h"
#include "host/scene/scene_setup.h"

namespace romp::run {

struct ReducedRunOptions {
  std::string model;  // empty: a full-order run
  std::string quadrature = "eulerian";
  std::string projection = "velocity";
  Index samples = 0;  // 0: every material point
  std::uint64_t seed = 0;
  double cfl = 0.0;              // > 0: the reduced substeps' CFL number instead of the scene's time.cfl
  bool no_frame_graphs = false;  // launch each substep's kernels instead of replaying a frame's graph
};

// Adds --rom, --quadrature, --projection, --samples, --sample-seed, --rom-cfl and --no-frame-graphs to `run`.
void add_reduced_run_options(CLI::App& run, ReducedRunOptions& options);

// The simulation of a reduced-order run: loads the model, encodes the scene's initial state and logs
// what it loaded.
std::unique_ptr<Simulation> make_reduced_simulation(const ReducedRunOptions& options, const Exec& exec,
                                                    const scene::SceneSetup& setup);

}  // namespace romp::run
