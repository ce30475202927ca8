// The deformation map's layer shapes and the rules of its normalisation.
#include "nn/rom/map_layout.h"

#include <cmath>
#include <utility>

namespace romp::nn::rom {

std::vector<std::array<std::int64_t, 2>> map_layer_shapes(const MapArchitecture& architecture) {
  std::vector<std::array<std::int64_t, 2>> shapes;
  std::int64_t in = architecture.latent + 3;
  for (std::int64_t k = 0; k <= architecture.hidden_layers; ++k) {
    const std::int64_t out = k == architecture.hidden_layers ? 3 : architecture.width;
    shapes.push_back({out, in});
    in = out;
  }
  return shapes;
}

std::string normalisation_problem(const MapNormalisationValues& n) {
  const std::pair<const char*, const std::array<float, 3>*> parts[] = {
      {"X_min", &n.X_min}, {"X_max", &n.X_max}, {"u_mean", &n.u_mean}, {"u_std", &n.u_std}};
  for (const auto& [name, values] : parts) {
    for (float value : *values)
      if (!std::isfinite(value)) return std::string(name) + " is not finite";
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (!(n.X_max[axis] > n.X_min[axis])) return "the bounding box X_min .. X_max is empty in some axis";
  }
  for (float value : n.u_std)
    if (!(value > 0.0f)) return "u_std must be positive";
  return "";
}

}  // namespace romp::nn::rom
