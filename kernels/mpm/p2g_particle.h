// What one particle scatters in P2G, computed once and shared by the portable kernel (atomics on the
// grid per node) and the tiled kernel (a block's nodes accumulated locally first).
#pragma once

#include "kernels/core/atomic.h"
#include "kernels/material/material.h"
#include "kernels/math/atomic_planes.h"
#include "kernels/math/finite.h"
#include "kernels/mpm/bspline.h"
#include "kernels/mpm/mls_transfer.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/stencil_nodes.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {

struct P2GParticle {
  QuadraticStencil<float> stencil;
  float mass;
  Vec3<float> momentum;  // m v, plus this substep's load impulses
  Mat3<float> affine;    // APIC's m C and the MLS stress impulse, applied through (x_i − x_p)
  Vec3<float> v;         // for PIC/FLIP's velocity before forces

  ROMP_HD P2GParticle(const ParticleView& particles, const GridView& grid, const StepParams& step, Index p)
      : stencil(particles.x.load(p), grid.inverse_dx), mass(particles.mass[p]), v(particles.v.load(p)) {
    const Vec3<float> x = particles.x.load(p);
    const Mat3<float> F = particles.F.load(p);
    const material::MaterialParams<float>& params = step.materials[particles.material[p]];
    const Mat3<float> P = particle_first_piola(step, params, p, F);
    if (!is_finite(P)) atomic_min(&step.first_failure[int(Stage::P2G)], std::int64_t(p));
    const float k = stress_factor(step.dt, particles.volume0[p], inverse_inertia(grid.inverse_dx));
    affine =
        step.transfer == Transfer::Apic ? affine_momentum(k, P, F, mass, particles.C.load(p)) : stress_impulse(k, P, F);
    momentum = mass * v;
    for (Index l = 0; l < step.loads.size(); ++l)
      if (step.loads[l].contains(x)) momentum += (mass * step.dt) * step.loads[l].acceleration;
    momentum += step.dt * traction_force(step, particles, p);
  }

  // The weight of node base + (i, j, k) and the momentum it receives.
  ROMP_HD float weight(int i, int j, int k) const { return stencil.weight(i, j, k); }
  ROMP_HD Vec3<float> momentum_to(int i, int j, int k, float w, float dx) const {
    return node_momentum(w, momentum, affine, stencil.offset(i, j, k, dx));
  }
};

// Adds a particle's mass and momentum to its 27 stencil nodes of the grid with atomics: the portable kernel's
// scatter, and the tiled kernel's for a particle that has left the block it was sorted into. kActiveNodesOnly:
// the grid holds only some of the stencils' blocks (particle_to_grid_active_nodes), the others' shares are
// dropped.
template <bool kActiveNodesOnly = false>
ROMP_HD inline void scatter_to_grid(const P2GParticle& particle, const GridView& grid) {
  const bool flip = grid.keeps_old_velocity();
  const StencilNodes nodes(particle.stencil, grid.table);
  for_each_stencil_offset([&](int i, int j, int k) {
    if (kActiveNodesOnly && !nodes.active(i, j, k)) return;
    const float w = particle.weight(i, j, k);
    const Index n = nodes.node(i, j, k);
    atomic_add(&grid.mass[n], w * particle.mass);
    atomic_add(grid.velocity, n, particle.momentum_to(i, j, k, w, grid.dx));
    // FLIP needs the transferred velocity without this step's forces.
    if (flip) atomic_add(grid.velocity_old, n, (w * particle.mass) * particle.v);
  });
}

}  // namespace romp::mpm
