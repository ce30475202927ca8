// read_ground_truth: a `romp run` snapshot as the trajectory and simulation constants neural-law training fits.
#pragma once

#include <string>
#include <vector>

#include "host/scene/scene.h"
#include "nn/diffmpm/mpm_step.h"
#include "nn/nclaw/trajectory.h"

namespace romp::nclaw {

struct GroundTruth {
  nn::diffmpm::DiffMpmConfig config;                    // the snapshot's scene: grid, dt, gravity, walls
  nn::nclaw::Trajectory trajectory;                     // float32 on the CPU, frames 0 .. last
  std::vector<scene::MaterialSpecification> materials;  // the scene's, for the oracles that know them
};

// The differentiable step's constants for `scene`: grid, dt, gravity, walls. The scene must be one
// the step reproduces: a fixed dt, APIC transfers, frictionless walls and no colliders, Dirichlet
// groups or pokes; otherwise a romp::Error that starts with `label` says which.
nn::diffmpm::DiffMpmConfig differentiable_config(const scene::Scene& scene, const std::string& label);

// Reads frames 0 .. `last_frame` (all frames when negative) of the snapshot at `path`. The scene
// stored in it must pass differentiable_config, with one frame per substep, and every frame must
// hold x, v, F and C. Throws romp::Error naming the file and what is missing or unsupported.
GroundTruth read_ground_truth(const std::string& path, int64_t last_frame = -1);

}  // namespace romp::nclaw
