// The named materials of the papers romp reproduces, so scenes, tests and benchmarks share one
// definition, and the conversion of a scene's material to the engine's parameters.
#pragma once

#include <optional>
#include <string>

#include "host/full_order_sim.h"
#include "host/scene/scene.h"

namespace romp {

// Ground-truth materials of the neural-constitutive-law paper (App. B; values from the authors'
// code, listed in shared/papers/README.md). All have density 1e3 kg/m^3.
enum class NclawMaterial { Jelly, Sand, Plasticine, Water };

// "jelly", "sand", "plasticine", "water", or nothing.
std::optional<NclawMaterial> nclaw_material_named(const std::string& name);
scene::MaterialSpecification nclaw_preset(NclawMaterial which);

// Lamé parameters from E and ν, the return-map parameters, and the density for the CFL condition.
MaterialSpec to_material_spec(const scene::MaterialSpecification& material);
MaterialSpec nclaw_material(NclawMaterial which);

}  // namespace romp
