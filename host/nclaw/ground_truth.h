// read_ground_truth: a `romp run` snapshot as the trajectory and simulation constants neural-law training fits.
#pragma once

#include <string>

#include "nn/diffmpm/mpm_step.h"
#include "nn/nclaw/trajectory.h"

namespace romp::nclaw {

struct GroundTruth {
  nn::DiffMpmConfig config;     // the snapshot's scene: grid, dt, gravity, walls
  nn::Trajectory trajectory;    // float32 on the CPU, frames 0 .. last
};

// Reads frames 0 .. `last_frame` (all frames when negative) of the snapshot at `path`. The scene
// stored in the snapshot must be one the differentiable step reproduces: a fixed dt with one substep
// per frame, APIC transfers, frictionless walls and no colliders, Dirichlet groups or pokes; every
// frame must hold x, v, F and C. Throws romp::Error naming the file and what is missing or unsupported.
GroundTruth read_ground_truth(const std::string& path, int64_t last_frame = -1);

}  // namespace romp::nclaw
