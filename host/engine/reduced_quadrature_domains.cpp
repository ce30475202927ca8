// The domain quadrature: every material point through its particle domain's corners, placed by g.
#include <fmt/format.h>

#include <algorithm>

#include "host/engine/reduced_quadrature.h"
#include "kernels/rom/domain_quadrature.h"
#include "kernels/rom/reduced_dynamics.h"

namespace romp::engine {

DomainQuadrature::DomainQuadrature(const Exec& exec, const ReferenceBody& reference, const mpm::DomainInit& domains,
                                   const std::vector<std::int32_t>& point_domain, int latent,
                                   float enrichment_threshold)
    : latent_(latent), enrichment_threshold_(enrichment_threshold), domains_(exec.backend, domains) {
  ROMP_CHECK(!domains.empty() && Index(point_domain.size()) == reference.count,
             "the domain quadrature needs a body sampled with particle domains (the object's domains = true)");
  for (std::size_t p = 0; p < point_domain.size(); ++p)
    ROMP_CHECK(point_domain[p] != mpm::kNoDomain,
               fmt::format("the domain quadrature needs every material point in a particle domain; point {} has "
                           "none (an object without domains = true, or a released region)",
                           p));
  const Index corners = domains_.corner_count();
  corner_X_ = DeviceBuffer<float>::from_host(exec.backend, domains.corner_x);
  corner_dg_dxhat_ = DeviceBuffer<float>(exec.backend, 3 * Index(latent_) * corners);
  point_domain_ = DeviceBuffer<std::int32_t>::from_host(exec.backend, point_domain);
  // Every material point is a quadrature point: its mass, volume and tables never change.
  reference.copy_to(points_);
}

mpm::ParticleView DomainQuadrature::build(const Exec& exec, const DeformationMap& map, const SampleSet& samples,
                                          Span<const float> xhat, Span<const float> vhat) {
  const mpm::DomainView domains = domains_.view();
  const Index corners = domains.corners;
  // x_α = g(X_α; x̂) and v_α = (∂g/∂x̂)(X_α) v̂ at every corner, then each point as its domain places it.
  map.evaluate(exec, xhat, Vec3Planes<const float>(corner_X_.data(), corners),
               {domains.x, {}, corner_dg_dxhat_.span()});
  rom::latent_to_point_velocity(exec, latent_, corner_dg_dxhat_.span(), vhat, domains.v);
  mpm::ParticleView points = points_.view();
  points.domain = point_domain_.span();
  rom::points_from_corners(exec, points, domains);
  // The samples' corners, of which their grid is built. The sample count is the run's: this grows once.
  sample_corner_count_ = mpm::kDomainCorners * samples.count();
  if (sample_corners_.size() < 3 * sample_corner_count_)
    sample_corners_ = DeviceBuffer<float>(exec.backend, 3 * sample_corner_count_);
  rom::gather_sample_corners(exec, samples.index(), point_domain_.span(), domains,
                             Vec3Planes<float>(sample_corners_.data(), sample_corner_count_));
  points_so_far_ += points_.count;
  return points;
}

void DomainQuadrature::particles_to_grid(const Exec& exec, const mpm::ParticleView& points, const mpm::GridView& grid,
                                         const mpm::StepParams& step) {
  const mpm::DomainView domains = domains_.view();
  if (enriches()) mpm::mark_enrichment(exec, points, domains, step, enrichment_threshold_);
  mpm::particles_to_corners(exec, points, domains, step);
  mpm::corners_to_active_nodes(exec, domains, grid, step);
}

float DomainQuadrature::cfl_length(float dx) const { return enriches() ? std::min(dx, domains_.smallest_edge()) : dx; }

Vec3Planes<const float> DomainQuadrature::sample_stencil_points(const SampleSet&) const {
  return Vec3Planes<const float>(sample_corners_.data(), sample_corner_count_);
}

void DomainQuadrature::grid_to_samples(const Exec& exec, SampleSet& samples, const mpm::GridView& grid,
                                       const mpm::StepParams& step) {
  rom::grid_to_domain_samples(exec, samples.points().view(), samples.index(), point_domain_.span(), domains_.view(),
                              sample_stencil_points(samples), grid, step);
}

mpm::PointSource DomainQuadrature::failure_source() const {
  return {Vec3Planes<const float>(points_.x.data(), points_.count),
          Vec3Planes<const float>(points_.X.data(), points_.count),
          {}};
}

std::string DomainQuadrature::describe(const mpm::FailedPoint& point) const {
  return fmt::format("material point {} (a quadrature point, through its particle domain)", point.particle);
}

mpm::PointSource DomainQuadrature::outside_source() const {
  const Index corners = domains_.corner_count();
  return {domains_.corner_positions(), Vec3Planes<const float>(corner_X_.data(), corners), {}};
}

std::string DomainQuadrature::describe_outside(std::int64_t corner) const {
  return fmt::format("particle domain corner {}", corner);
}

}  // namespace romp::engine
