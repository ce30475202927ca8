// P2G: particles scatter mass, momentum and the MLS stress impulse to their 27 grid nodes.
#include "kernels/core/for_each.h"
#include "kernels/mpm/p2g_particle.h"

namespace romp::mpm {
namespace {

template <bool kActiveNodesOnly>
struct ParticleToGrid {
  ParticleView particles;
  GridView grid;
  StepParams step;
  ROMP_HD void operator()(Index p) const {
    if (particles.has_domain(p)) return;  // its domain's corners carry it to the grid
    scatter_to_grid<kActiveNodesOnly>(P2GParticle(particles, grid, step, p), grid);
  }
};

}  // namespace

void particle_to_grid(const Exec& exec, const ParticleView& particles, const GridView& grid, const StepParams& step) {
  for_each(exec, particles.count, ParticleToGrid<false>{particles, grid, step});
}

void particle_to_grid_active_nodes(const Exec& exec, const ParticleView& particles, const GridView& grid,
                                   const StepParams& step, Span<const std::int64_t> live) {
  for_each_bounded(exec, particles.count, live, ParticleToGrid<true>{particles, grid, step});
}

}  // namespace romp::mpm
