// TracerSet: embedding in the domains, grid advection of the rest, and the merged state.
#include "host/engine/tracer_set.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "kernels/core/error.h"
#include "kernels/mpm/tracers.h"

namespace romp::engine {
namespace {

// The edge of the lattice cells the domains are (the same for every domain), from their corners' extent.
double lattice_spacing(const mpm::DomainInit& domains) {
  double smallest = INFINITY, largest = 0.0;
  for (Index d = 0; d < domains.count(); ++d) {
    Vec3<double> low = domains.corner_position(domains.corner_x, d, 0), high = low;
    for (int alpha = 1; alpha < mpm::kDomainCorners; ++alpha) {
      const Vec3<double> x = domains.corner_position(domains.corner_x, d, alpha);
      for (int a = 0; a < 3; ++a) {
        low[a] = std::min(low[a], x[a]);
        high[a] = std::max(high[a], x[a]);
      }
    }
    for (int a = 0; a < 3; ++a) {
      smallest = std::min(smallest, high[a] - low[a]);
      largest = std::max(largest, high[a] - low[a]);
    }
  }
  ROMP_CHECK(largest <= smallest * (1.0 + 1e-4),
             fmt::format("tracers: the particle domains are cells of different sizes ({} to {} m); points can be "
                         "embedded in domains of one lattice spacing only",
                         smallest, largest));
  return smallest;
}

std::vector<Vec3<double>> points_of(const std::vector<float>& planes, Index n) {
  std::vector<Vec3<double>> points(std::size_t(n), Vec3<double>::zero());
  for (Index p = 0; p < n; ++p) points[std::size_t(p)] = Vec3<double>(planes[p], planes[n + p], planes[2 * n + p]);
  return points;
}

}  // namespace

TracerSet::TracerSet(const Exec& exec, const std::vector<float>& X, const mpm::DomainInit& domains)
    : count_(Index(X.size() / 3)), layout_(domains) {
  ROMP_CHECK(count_ > 0 && X.size() == std::size_t(3 * count_),
             fmt::format("tracer positions come as 3 planes, got {} values", X.size()));
  const std::vector<Vec3<double>> points = points_of(X, count_);
  if (!domains.empty())
    embedded_ = geometry::embed_points(points, domains, 0, lattice_spacing(domains));
  else
    embedded_.domain.assign(std::size_t(count_), -1);
  for (Index p = 0; p < count_; ++p)
    if (embedded_.domain[std::size_t(p)] < 0) on_grid_.push_back(p);
  const Index n = Index(on_grid_.size());
  std::vector<float> grid_x(std::size_t(3 * n));
  for (Index i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) grid_x[std::size_t(a * n + i)] = X[std::size_t(a * count_ + on_grid_[std::size_t(i)])];
  x_ = DeviceBuffer<float>::from_host(exec.backend, grid_x, exec.stream);
  v_ = DeviceBuffer<float>::from_host(exec.backend, std::vector<float>(grid_x.size(), 0.0f), exec.stream);
}

void TracerSet::advect(const Exec& exec, const mpm::GridView& grid, const mpm::StepParams& step) {
  const Index n = Index(on_grid_.size());
  if (n > 0) mpm::advect_tracers(exec, Vec3Planes<float>(x_.data(), n), Vec3Planes<float>(v_.data(), n), grid, step);
}

std::vector<float> TracerSet::positions(const Exec& exec, const mpm::ParticleDomains* domains) const {
  const bool held = domains && embedded_count() > 0;
  return merged(x_.to_host(exec.stream), held ? domains->corner_positions_on_host(exec) : std::vector<float>{});
}

std::vector<float> TracerSet::velocities(const Exec& exec, const mpm::ParticleDomains* domains) const {
  const bool held = domains && embedded_count() > 0;
  return merged(v_.to_host(exec.stream), held ? domains->corner_velocities_on_host(exec) : std::vector<float>{});
}

std::vector<float> TracerSet::merged(const std::vector<float>& values, const std::vector<float>& corner_values) const {
  std::vector<float> out(std::size_t(3 * count_), 0.0f);
  if (embedded_count() > 0) {
    const std::vector<Vec3<double>> held = embedded_.interpolate(layout_, corner_values);
    for (Index p = 0; p < count_; ++p)
      if (embedded_.domain[std::size_t(p)] >= 0)
        for (int a = 0; a < 3; ++a) out[std::size_t(a * count_ + p)] = float(held[std::size_t(p)][a]);
  }
  const Index n = Index(on_grid_.size());
  for (Index i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a)
      out[std::size_t(a * count_ + on_grid_[std::size_t(i)])] = values[std::size_t(a * n + i)];
  return out;
}

}  // namespace romp::engine
