// `romp demo`: the training scene of the neural-constitutive-law paper, run full-order with a stage table.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "host/material_library.h"
#include "kernels/core/exec.h"

namespace romp {

struct DemoResult {
  Index particles = 0;
  std::int64_t substeps = 0;
  double simulated_seconds = 0.0;
  double wall_seconds = 0.0;
  Vec3<double> center_of_mass{0.0, 0.0, 0.0};
  double kinetic_energy = 0.0;  // J
  std::vector<std::pair<std::string, double>> stage_seconds;
};

// A cube of side 0.5 m centred in the unit box, 10^3 particles on a 20^3 grid, thrown with linear
// velocity (1, -1.5, -2) m/s and angular velocity (4, 4, 4) rad/s under gravity, between
// frictionless walls 3 cells thick, stepped with Δt = 5e-4 s (Ma et al. 2023, App. B).
DemoResult run_cube_demo(const Exec& exec, NclawMaterial material, int substeps);

// The stage table printed at the end of a run: seconds and share of each stage.
std::string stage_table(const std::vector<std::pair<std::string, double>>& stage_seconds);

}  // namespace romp
