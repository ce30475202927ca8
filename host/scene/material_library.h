// The named materials of the papers romp reproduces, so scenes, tests and benchmarks share one
// definition, and the conversion of a scene's material to the engine's parameters.
#pragma once

#include <optional>
#include <string>

#include "host/engine/sim_config.h"
#include "host/scene/scene.h"
#include "kernels/material/lame.h"

namespace romp::scene {

// Ground-truth materials of the neural-constitutive-law paper (App. B; values from the authors'
// code, listed in shared/papers/README.md). All have density 1e3 kg/m^3.
enum class NclawMaterial { Jelly, Sand, Plasticine, Water };

// "jelly", "sand", "plasticine", "water", or nothing.
std::optional<NclawMaterial> nclaw_material_named(const std::string& name);
scene::MaterialSpecification nclaw_preset(NclawMaterial which);

// Lamé parameters from E and ν, the return-map parameters, and the density for the CFL condition;
// for a neural material, the law file and its stiffness at rest (neural_law_at_rest).
engine::MaterialSpec to_material_spec(const scene::MaterialSpecification& material);

// μ and λ of a law file's elastic law linearised at F = I (nn::nclaw::rest_stiffness), for the CFL
// condition. Throws romp::Error naming the file when it is not a law file or its law does not
// resist compression at rest.
material::Lame<float> neural_law_at_rest(const std::string& law_file);
engine::MaterialSpec nclaw_material(NclawMaterial which);

}  // namespace romp::scene
