// The Lagrangian quadrature (ROM paper, Alg. 3): material points as quadrature points.
#include <fmt/format.h>

#include "host/engine/reduced_quadrature.h"
#include "kernels/core/gather_planes.h"
#include "kernels/rom/reduced_dynamics.h"
#include "kernels/rom/stencil_neighbours.h"

namespace romp::engine {

LagrangianQuadrature::LagrangianQuadrature(const Exec& exec, const ReferenceBody& reference, int latent, float dx,
                                           bool search)
    : reference_(reference), latent_(latent), search_(search), inverse_dx_(1.0f / dx) {
  const Index n = reference.count;
  if (search_) {
    positions_ = DeviceBuffer<float>(exec.backend, 3 * n);
    marked_ = DeviceBuffer<std::int32_t>(exec.backend, n);
    index_ = DeviceBuffer<std::int32_t>(exec.backend, n);
    neighbours_so_far_ = DeviceBuffer<std::int64_t>(exec.backend, 1);
    neighbours_so_far_.fill_zero(exec.stream);
    // Room for every material point: the neighbours' count stays on the device, so it cannot size the buffers
    // (and it changes from substep to substep); launches over them stop at the count.
    points_.allocate(exec.backend, n);
  } else {
    // Every material point is a quadrature point: its mass, volume and tables never change.
    reference.copy_to(points_);
  }
  dg_dxhat_ = DeviceBuffer<float>(exec.backend, 3 * Index(latent_) * n);
}

mpm::ParticleView LagrangianQuadrature::build(const Exec& exec, const DeformationMap& map, const SampleSet& samples,
                                              Span<const float> xhat, Span<const float> vhat) {
  const Index n = reference_.count;
  if (search_) {
    // Alg. 3, steps 2-3: the points whose stencils reach the samples' grid nodes, found from g's
    // positions at every point, compacted and counted on the device in reference order.
    map.evaluate(exec, xhat, Vec3Planes<const float>(reference_.X.data(), n),
                 {Vec3Planes<float>(positions_.data(), n), {}, {}});
    const Span<const std::uint64_t> near_bases = neighbourhood_.near_bases(exec, samples.x(), inverse_dx_);
    rom::mark_stencil_neighbours(exec, Vec3Planes<const float>(positions_.data(), n), inverse_dx_, near_bases,
                                 marked_.span());
    neighbours_ = select_.select_on_device(exec, marked_.span(), 1, index_.span());
    add_count(exec, neighbours_, neighbours_so_far_.span());
    // The reference state and the positions the search saw, so P2G bins each point exactly where it was found.
    GatheredArrays arrays = reference_.arrays_into(points_);
    arrays.add(positions_.span(), points_.x.span(), 3);
    gather_arrays(exec, arrays, n, index_.span(), neighbours_);
  } else {
    points_so_far_ += n;
  }
  // Searching, the kinematics run over the neighbours' slots and stop at their count.
  const Span<float> dg_dxhat = dg_dxhat_.span();
  const Vec3Planes<float> x = search_ ? Vec3Planes<float>() : Vec3Planes<float>(points_.x.data(), n);
  map.evaluate(exec, xhat, Vec3Planes<const float>(points_.X.data(), n),
               {x, Mat3Planes<float>(points_.F.data(), n), dg_dxhat}, neighbours_);
  rom::latent_to_point_velocity(exec, latent_, dg_dxhat, vhat, Vec3Planes<float>(points_.v.data(), n), neighbours_);
  return points_.view();
}

Index LagrangianQuadrature::last_count(const Exec& exec) const {
  if (!search_) return points_.count;
  return neighbours_.empty() ? 0 : Index(download(exec.backend, neighbours_, exec.stream)[0]);  // 0 before a build
}

std::int64_t LagrangianQuadrature::points_so_far(const Exec& exec) const {
  return search_ ? download(exec.backend, neighbours_so_far_.prefix(1), exec.stream)[0] : points_so_far_;
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
