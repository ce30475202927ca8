#include "bench/suites/random_map.h"

#include <torch/torch.h>

#include "nn/rom/deformation_map.h"
#include "nn/rom/fused_map.h"

namespace romp::bench {

rom::DeformationMapWeights random_map(const geometry::Bounds& box) {
  using nn::rom::DeformationMap;
  torch::manual_seed(0);
  const torch::Tensor lower = torch::tensor({float(box.low[0]), float(box.low[1]), float(box.low[2])});
  const torch::Tensor upper = torch::tensor({float(box.high[0]), float(box.high[1]), float(box.high[2])});
  DeformationMap map(nn::rom::MapArchitecture{6, 5, 30},
                     nn::rom::MapNormalisation{lower, upper, torch::zeros({3}), 1e-3f * torch::ones({3})});
  return nn::rom::fused_weights(*map);
}

}  // namespace romp::bench
