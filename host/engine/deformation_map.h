// DeformationMap: the neural map g(X; x̂) of a reduced simulation, its weights on the device, evaluated
// with the fused kernels (kernels/rom) at any reference points.
#pragma once

#include <cstdint>

#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/rom/deformation_map_eval.h"

namespace romp::engine {

class DeformationMap {
 public:
  DeformationMap(Backend backend, rom::DeformationMapWeights weights);

  int latent() const { return weights_.latent; }
  rom::DeformationMapView<float> view() const;
  // g, ∇_X g and ∂g/∂x̂ (whichever `out` asks for) at the n reference points X for x̂ on the device; with
  // `live`, a count on the device, at the first live[0] of them only.
  void evaluate(const Exec& exec, Span<const float> xhat, Vec3Planes<const float> X,
                const rom::DeformationMapOutputs<float>& out, Span<const std::int64_t> live = {}) const;

 private:
  rom::DeformationMapWeights weights_;
  DeviceBuffer<float> parameters_;
};

}  // namespace romp::engine
