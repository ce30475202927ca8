// A trained deformation map as the fused evaluator of kernels/rom reads it: the layers' weights and
// biases packed in evaluation order, and the normalisation, in float.
#pragma once

#include "kernels/rom/deformation_map_eval.h"
#include "nn/rom/deformation_map.h"

namespace romp::nn::rom {

// Throws romp::Error when the map exceeds the fused kernel's limits (kernels/rom/deformation_map_eval.h).
romp::rom::DeformationMapWeights fused_weights(const DeformationMapImpl& map);

}  // namespace romp::nn::rom
