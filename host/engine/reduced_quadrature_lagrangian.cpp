// The Lagrangian quadrature (ROM paper, Alg. 3): material points as quadrature points.
#include <fmt/format.h>

#include "host/engine/reduced_quadrature.h"
#include "kernels/core/gather_planes.h"
#include "kernels/rom/reduced_dynamics.h"
#include "kernels/rom/stencil_neighbours.h"

namespace romp::engine {

LagrangianQuadrature::LagrangianQuadrature(const Exec& exec, const ReferenceBody& reference, int latent, float dx,
                                           bool search)
    : reference_(reference), latent_(latent), dx_(dx), search_(search) {
  const Index n = reference.count;
  if (search_) {
    positions_ = DeviceBuffer<float>(exec.backend, 3 * n);
    marked_ = DeviceBuffer<std::int32_t>(exec.backend, n);
    index_ = DeviceBuffer<std::int32_t>(exec.backend, n);
  } else {
    // Every material point is a quadrature point: its mass, volume and tables never change.
    reference.copy_to(points_);
    dg_dxhat_ = DeviceBuffer<float>(exec.backend, 3 * Index(latent_) * n);
  }
}

mpm::ParticleView LagrangianQuadrature::build(const Exec& exec, const DeformationMap& map, const SampleSet& samples,
                                              Span<const float> xhat, Span<const float> vhat) {
  const Index n = reference_.count;
  if (search_) {
    // Alg. 3, steps 2-3: the points whose stencils reach the samples' grid nodes, found from g's
    // positions at every point.
    const float inverse_dx = 1.0f / dx_;
    map.evaluate(exec, xhat, Vec3Planes<const float>(reference_.X.data(), n),
                 {Vec3Planes<float>(positions_.data(), n), {}, {}});
    const Span<const std::uint64_t> near_bases = neighbourhood_.near_bases(exec, samples.x(), inverse_dx);
    rom::mark_stencil_neighbours(exec, Vec3Planes<const float>(positions_.data(), n), inverse_dx, near_bases,
                                 marked_.span());
    // Compacted on the device, in reference order.
    const Index count = select_(exec, marked_.span(), 1, index_.span());
    points_.resize(exec.backend, count);
    const Span<const std::int32_t> index = index_.prefix(count);
    // The reference state and the positions the search saw, so P2G bins each point exactly where it was found.
    GatheredArrays arrays = reference_.arrays_into(points_);
    arrays.add(positions_.span(), points_.x.span(), 3);
    gather_arrays(exec, arrays, n, index);
    if (dg_dxhat_.size() < 3 * Index(latent_) * count)
      dg_dxhat_ = DeviceBuffer<float>(exec.backend, 3 * Index(latent_) * points_.capacity);
  }
  const Index q = points_.count;
  points_so_far_ += q;
  const Span<float> dg_dxhat(dg_dxhat_.data(), 3 * Index(latent_) * q);
  const Vec3Planes<float> x = search_ ? Vec3Planes<float>() : Vec3Planes<float>(points_.x.data(), q);
  map.evaluate(exec, xhat, Vec3Planes<const float>(points_.X.data(), q),
               {x, Mat3Planes<float>(points_.F.data(), q), dg_dxhat});
  rom::latent_to_point_velocity(exec, latent_, dg_dxhat, vhat, Vec3Planes<float>(points_.v.data(), q));
  return points_.view();
}

Vec3Planes<float> LagrangianQuadrature::material_positions() {
  return Vec3Planes<float>(points_.x.data(), points_.count);
}

mpm::PointSource LagrangianQuadrature::failure_source() const {
  return {Vec3Planes<const float>(points_.x.data(), points_.count),
          Vec3Planes<const float>(points_.X.data(), points_.count),
          search_ ? index_.prefix(points_.count) : Span<const std::int32_t>()};
}

std::string LagrangianQuadrature::describe(const mpm::FailedPoint& point) const {
  return fmt::format("material point {} (a quadrature point)", point.particle);
}

}  // namespace romp::engine
