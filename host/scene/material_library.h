// A scene's material as the engine's parameters (a learned law's stiffness at rest read through LibTorch),
// and the named materials (named_materials.h) as engine materials.
#pragma once

#include <string>

#include "host/engine/sim_config.h"
#include "host/scene/named_materials.h"
#include "host/scene/scene.h"
#include "kernels/material/lame.h"

namespace romp::scene {

// Lamé parameters from E and ν, the return-map parameters, and the density for the CFL condition;
// for a neural material, the law file and its stiffness at rest (neural_law_at_rest).
engine::MaterialSpec to_material_spec(const scene::MaterialSpecification& material);

// μ and λ of a law file's elastic law linearised at F = I (nn::nclaw::rest_stiffness), for the CFL
// condition. Throws romp::Error naming the file when it is not a law file or its law does not
// resist compression at rest.
material::Lame<float> neural_law_at_rest(const std::string& law_file);
engine::MaterialSpec nclaw_material(NclawMaterial which);

}  // namespace romp::scene
