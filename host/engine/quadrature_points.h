// QuadraturePoints: the points a reduced substep's MPM update reads (samples, material or Eulerian
// quadrature points), and ReferenceBody: the material points' reference state they are gathered from.
#pragma once

#include <cstdint>

#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/core/gather_planes.h"
#include "kernels/mpm/particle_set.h"

namespace romp::engine {

// Device planes in the layout of mpm::ParticleView, grown with headroom and reused: a substep's points
// are their prefix of `count`. C stays 0 (the reduced step's transfer is PIC, ROM paper Alg. 5).
struct QuadraturePoints {
  Index count = 0, capacity = 0;
  DeviceBuffer<float> x, X, v, C, F, mass, volume0;
  DeviceBuffer<std::int32_t> material, group, id, status;

  void allocate(Backend backend, Index n);
  // count = n, reallocating (with headroom) only when n exceeds the capacity; returns whether it did
  // (the contents are then uninitialised, C aside).
  bool resize(Backend backend, Index n);
  // These points: the points `index` of `source` (all but C, which stays 0, and status). `live`, where
  // given, is a count on the device: only the first live[0] of them are gathered, the rest left as they were.
  void gather_from(const Exec& exec, const QuadraturePoints& source, Span<const std::int32_t> index,
                   Span<const std::int64_t> live = {});
  mpm::ParticleView view();
};

// The material points in reference order: X (F = I there), mass, volume, material, Dirichlet group, id.
struct ReferenceBody {
  ReferenceBody(Backend backend, const mpm::ParticleInit& reference);

  Index count;
  DeviceBuffer<float> X, mass, volume0;
  DeviceBuffer<std::int32_t> material, group, id;

  // The reference state (X, mass, volume, material, group, id) of the material points `index`, in one launch.
  void gather(const Exec& exec, Span<const std::int32_t> index, QuadraturePoints& points) const;
  // The arrays `gather` copies, for a caller that gathers more of the same rows in that launch.
  GatheredArrays arrays_into(QuadraturePoints& points) const;
  // `points` as every material point, whose reference state never changes.
  void copy_to(QuadraturePoints& points) const;
};

}  // namespace romp::engine
