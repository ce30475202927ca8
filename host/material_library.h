// The named materials of the papers romp reproduces, so scenes, tests and benchmarks share one definition.
#pragma once

#include "host/full_order_sim.h"

namespace romp {

// Ground-truth materials of the neural-constitutive-law paper (App. B; values from the authors'
// code, listed in shared/papers/README.md). All have density 1e3 kg/m^3.
enum class NclawMaterial { Jelly, Sand, Plasticine, Water };

MaterialSpec nclaw_material(NclawMaterial which);

}  // namespace romp
