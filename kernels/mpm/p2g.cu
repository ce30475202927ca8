// P2G: particles scatter mass, momentum and the MLS stress impulse to their 27 grid nodes.
#include "kernels/core/for_each.h"
#include "kernels/math/atomic_planes.h"
#include "kernels/mpm/p2g_particle.h"
#include "kernels/mpm/stencil_nodes.h"

namespace romp::mpm {
namespace {

struct ParticleToGrid {
  ParticleView particles;
  GridView grid;
  StepParams step;
  ROMP_HD void operator()(Index p) const {
    if (particles.has_domain(p)) return;  // its domain's corners carry it to the grid
    const P2GParticle particle(particles, grid, step, p);
    const bool flip = grid.keeps_old_velocity();
    const StencilNodes nodes(particle.stencil, grid.table);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) {
          const float w = particle.weight(i, j, k);
          const Index n = nodes.node(i, j, k);
          const Vec3<float> contribution = particle.momentum_to(i, j, k, w, grid.dx);
          atomic_add(&grid.mass[n], w * particle.mass);
          atomic_add(grid.velocity, n, contribution);
          // FLIP needs the transferred velocity without this step's forces.
          if (flip) atomic_add(grid.velocity_old, n, (w * particle.mass) * particle.v);
        }
  }
};

}  // namespace

void particle_to_grid(const Exec& exec, const ParticleView& particles, const GridView& grid, const StepParams& step) {
  for_each(exec, particles.count, ParticleToGrid{particles, grid, step});
}

}  // namespace romp::mpm
