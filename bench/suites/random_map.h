// A deformation map of the ROM paper's size (r = 6, 5 hidden layers of 30) with LibTorch's seeded
// initialisation: what the cost suites evaluate when a trained model is not needed (the cost of g does
// not depend on its weights).
#pragma once

#include "host/geometry/bounds.h"
#include "kernels/rom/deformation_map_eval.h"

namespace romp::bench {

// Over reference positions in `box`; its displacements are about a millimetre.
rom::DeformationMapWeights random_map(const geometry::Bounds& box);

}  // namespace romp::bench
