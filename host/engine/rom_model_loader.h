// A trained reduced-order model for a scene: the map's weights for ReducedSim and the generalized
// coordinates of the scene's initial state (the encoder applied to it, ROM paper Sec. 4.1).
#pragma once

#include <string>
#include <vector>

#include "kernels/mpm/particle_set.h"
#include "kernels/rom/deformation_map_eval.h"

namespace romp::engine {

struct LoadedReducedModel {
  rom::DeformationMapWeights map;
  std::vector<float> xhat;  // x̂ at t = 0
  std::string description;  // latent size, architecture, training errors, for the run's log
};

// Reads `path` and encodes `particles` (the scene's initial state). The encoder reads material points
// by index, so the scene must sample the same points as the snapshots the model was trained on (the
// same scene file and parameters that change no geometry): a different count is an error naming the
// file and both counts.
LoadedReducedModel load_reduced_model(const std::string& path, const mpm::ParticleInit& particles);

}  // namespace romp::engine
