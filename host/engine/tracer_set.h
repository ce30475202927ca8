// TracerSet: passive points a full-order run carries without their acting on it, the ROM paper's
// tracer-particle baseline for super-resolution (Sec. 5.2.1, Table 4; romp run --output-points).
// Where the run has particle domains, a point that a domain holds rides in it at fixed trilinear
// coordinates: the corners' motion is the material's there (an enriched corner moves by its own
// velocity, which the grid does not carry). Every other point is carried by the grid's velocity
// (kernels/mpm/tracers.h).
#pragma once

#include <vector>

#include "host/geometry/embedded_mesh.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/mpm/particle_domains.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/step.h"

namespace romp::engine {

// What carries a tracer in a run with particle domains.
enum class TracerCarrier {
  Material,  // the domain that holds it at the start, else the grid
  Grid,      // the grid's velocity everywhere: the classic tracer technique, blind to enriched corners
};

class TracerSet {
 public:
  // X: the points' positions at the start (3 planes). `domains`: the run's domain corners (indices and
  // positions) in the reference configuration, empty without domains; their lattice spacing must be one
  // for all.
  TracerSet(const Exec& exec, const std::vector<float>& X, const mpm::DomainInit& domains);

  // Moves the grid-carried points by one substep, after the grid update (as G2P).
  void advect(const Exec& exec, const mpm::GridView& grid, const mpm::StepParams& step);

  // Positions and velocities now, 3 planes in the order of X; `domains` is the run's (nullptr
  // without domains; read only when a point is embedded).
  std::vector<float> positions(const Exec& exec, const mpm::ParticleDomains* domains) const;
  std::vector<float> velocities(const Exec& exec, const mpm::ParticleDomains* domains) const;

  Index count() const { return count_; }
  Index embedded_count() const { return count_ - Index(on_grid_.size()); }

 private:
  // The grid-carried values from `values` (3 planes over them) and the domain-held ones interpolated
  // from `corner_values` (3 planes over the corners), in the order of X.
  std::vector<float> merged(const std::vector<float>& values, const std::vector<float>& corner_values) const;

  Index count_ = 0;
  mpm::DomainInit layout_;             // the domains' corners in the reference configuration
  geometry::EmbeddedPoints embedded_;  // domain -1: carried by the grid
  std::vector<Index> on_grid_;         // the grid-carried points' indices in X
  DeviceBuffer<float> x_, v_;          // the grid-carried points, 3 planes each
};

}  // namespace romp::engine
