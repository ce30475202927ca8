// The reduced simulation's map on the device.
#include "host/engine/deformation_map.h"

#include <utility>

namespace romp::engine {

DeformationMap::DeformationMap(Backend backend, rom::DeformationMapWeights weights)
    : weights_(std::move(weights)), parameters_(DeviceBuffer<float>::from_host(backend, weights_.parameters)) {}

rom::DeformationMapView<float> DeformationMap::view() const {
  return rom::map_view(weights_, Span<const float>(parameters_.data(), parameters_.size()));
}

void DeformationMap::evaluate(const Exec& exec, Span<const float> xhat, Vec3Planes<const float> X,
                              const rom::DeformationMapOutputs<float>& out, Span<const std::int64_t> live) const {
  rom::evaluate_deformation_map<float>(exec, view(), xhat, X, out, rom::MapKernel::Fastest, live);
}

}  // namespace romp::engine
