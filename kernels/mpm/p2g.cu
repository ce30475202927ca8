// P2G: particles scatter mass, momentum and the MLS stress impulse to their 27 grid nodes.
#include "kernels/core/atomic.h"
#include "kernels/core/for_each.h"
#include "kernels/math/finite.h"
#include "kernels/mpm/stencil_nodes.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {
namespace {

struct ParticleToGrid {
  ParticleView particles;
  GridView grid;
  StepParams step;

  ROMP_HD void operator()(Index p) const {
    const Vec3<float> x = particles.x.load(p);
    const Mat3<float> F = particles.F.load(p);
    const float mass = particles.mass[p];
    const material::MaterialParams<float>& params = step.materials[particles.material[p]];

    const Mat3<float> P = material::first_piola(params, F);
    if (!is_finite(P)) atomic_min(&step.first_failure[int(Stage::P2G)], std::int64_t(p));

    // MLS-MPM (Hu et al. 2018, Eq. 16 with D^-1 = 4/dx^2): the internal force enters as the affine
    // impulse -dt V0 D^-1 P F^T, applied through the same (x_i - x_p) moments as APIC's C.
    const float d_inverse = kInverseInertiaScale * grid.inverse_dx * grid.inverse_dx;
    Mat3<float> affine = (-step.dt * particles.volume0[p] * d_inverse) * times_transpose(P, F);
    if (step.transfer == Transfer::Apic) affine += mass * particles.C.load(p);

    const Vec3<float> v = particles.v.load(p);
    Vec3<float> momentum = mass * v;
    for (Index l = 0; l < step.loads.size(); ++l)
      if (step.loads[l].contains(x)) momentum += (mass * step.dt) * step.loads[l].acceleration;
    const bool flip = step.transfer == Transfer::PicFlip;

    const QuadraticStencil<float> stencil(x, grid.inverse_dx);
    const StencilNodes nodes(stencil, grid.table);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) {
          const float w = stencil.weight(i, j, k);
          const Index n = nodes.node(i, j, k);
          const Vec3<float> contribution = w * (momentum + affine * stencil.offset(i, j, k, grid.dx));
          atomic_add(&grid.mass[n], w * mass);
          for (int a = 0; a < 3; ++a) atomic_add(&grid.velocity.data()[a * grid.velocity.count() + n], contribution[a]);
          // FLIP needs the transferred velocity without this step's forces.
          if (flip)
            for (int a = 0; a < 3; ++a)
              atomic_add(&grid.velocity_old.data()[a * grid.velocity_old.count() + n], w * mass * v[a]);
        }
  }
};

}  // namespace

void particle_to_grid(const Exec& exec, const ParticleView& particles, const GridView& grid, const StepParams& step) {
  for_each(exec, particles.count, ParticleToGrid{particles, grid, step});
}

}  // namespace romp::mpm
