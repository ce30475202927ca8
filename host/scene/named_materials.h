// The named materials of the papers romp reproduces, as scene materials, so scenes, tests and benchmarks
// share one definition. Without LibTorch: the scene parser (and its fuzz harness) needs only these.
#pragma once

#include <optional>
#include <string>

#include "host/scene/scene.h"

namespace romp::scene {

// Ground-truth materials of the neural-constitutive-law paper (App. B; values from the authors'
// code, listed in shared/papers/README.md). All have density 1e3 kg/m^3.
enum class NclawMaterial { Jelly, Sand, Plasticine, Water };

// "jelly", "sand", "plasticine", "water", or nothing.
std::optional<NclawMaterial> nclaw_material_named(const std::string& name);
scene::MaterialSpecification nclaw_preset(NclawMaterial which);

}  // namespace romp::scene
