// G2P: particles gather velocity and its gradient, move, and update F; Dirichlet groups move rigidly.
#include "kernels/core/atomic.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/for_each.h"
#include "kernels/math/finite.h"
#include "kernels/mpm/mls_transfer.h"
#include "kernels/mpm/stencil_nodes.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {
namespace {

// The return map of particle p's material at its trial F: the plastic state updated, a non-finite result recorded
// as the plasticity stage's failure, and the F to store returned.
ROMP_HD Mat3<float> return_to_yield_surface(const ParticleView& particles, const StepParams& step, Index p,
                                            const Mat3<float>& F_trial) {
  const material::PlasticReturn<float> plastic =
      material::plastic_return(step.materials[particles.material[p]], F_trial);
  const Mat3<float>& F = plastic.F;
  if (!is_finite(F)) atomic_min(&step.first_failure[int(Stage::Plasticity)], std::int64_t(p));
  if (!particles.Jp.empty() && !(F == F_trial)) {
    particles.Jp[p] *= determinant(F_trial) / determinant(F);
    particles.plastic_strain[p] += plastic.strain;
  }
  return F;
}

// kReturnMap: with the return map (a kernel of its own, so that elastic scenes' G2P keeps its registers).
template <bool kReturnMap>
struct GridToParticle {
  ParticleView particles;
  GridView grid;
  StepParams step;
  GridCoverage coverage;

  ROMP_HD void operator()(Index p) const {
    if (particles.has_domain(p)) return;  // corners_to_particles moves it
    Vec3<float> x = particles.x.load(p);
    Mat3<float> F = particles.F.load(p);
    Vec3<float> v;
    Mat3<float> C;
    const std::int32_t group = particles.dirichlet_group[p];
    if (group != kNoDirichletGroup) {
      step.dirichlet[group].carry(step.dt, x, v, C, F);
    } else {
      const QuadraticStencil<float> stencil(x, grid.inverse_dx);
      const StencilNodes nodes(stencil, grid.table);
      VelocityGather<float> gathered;
      Vec3<float> dv_flip = Vec3<float>::zero();
      const bool flip = step.transfer == Transfer::PicFlip;
      for_each_stencil_offset([&](int i, int j, int k) {
        const float w = stencil.weight(i, j, k);
        const Index n = nodes.node(i, j, k);
        const Vec3<float> v_node = grid.velocity.load(n);
        gathered.add(w, v_node, stencil.offset(i, j, k, grid.dx));
        if (flip) dv_flip += w * (v_node - grid.velocity_old.load(n));
      });
      C = gathered.C(inverse_inertia(grid.inverse_dx));
      const Vec3<float>& v_pic = gathered.v;
      v = flip ? step.flip_alpha * (particles.v.load(p) + dv_flip) + (1.0f - step.flip_alpha) * v_pic : v_pic;
      x += step.dt * v;
      F = (Mat3<float>::identity() + step.dt * C) * F;
    }
    x = kept_inside_domain(step.domain, x, grid.dx);
    const bool returns = kReturnMap && group == kNoDirichletGroup;
    store_moved_particle(particles, step, p, x, v, C, F, returns ? return_to_yield_surface(particles, step, p, F) : F);
    if (!coverage.sorted_keys.empty()) record_left_grid(p, x);
  }

  ROMP_HD void record_left_grid(Index p, const Vec3<float>& x) const {
    if (!is_finite(x)) return;  // already G2P's failure: the run stops after this substep
    int base[3];
    for (int a = 0; a < 3; ++a) base[a] = QuadraticStencil<float>::base_node(x[a] * grid.inverse_dx);
    if (!stencil_within_blocks_around(base, coverage.sorted_keys[p])) atomic_max(&coverage.left[0], 1.0f);
  }
};

struct ProjectPlasticity {
  ParticleView particles;
  StepParams step;

  ROMP_HD void operator()(Index p) const {
    if (particles.dirichlet_group[p] != kNoDirichletGroup) return;
    particles.F.store(p, return_to_yield_surface(particles, step, p, particles.F.load(p)));
  }
};

struct RecordNonFiniteDeformation {
  Mat3Planes<const float> F;
  Span<std::int64_t> failure;  // one slot
  ROMP_HD void operator()(Index p) const {
    if (!is_finite(F.load(p))) atomic_min(&failure[0], std::int64_t(p));
  }
};

struct MaxSpeed {
  Vec3Planes<const float> v;
  Span<float> result;
  // Speeds are >= 0, so the float max of their values is the max of the speeds.
  ROMP_HD void operator()(Index p) const { atomic_max(&result[0], norm(v.load(p))); }
};

}  // namespace

void grid_to_particle(const Exec& exec, const ParticleView& particles, const GridView& grid, const StepParams& step,
                      const GridCoverage& coverage, bool return_map) {
  ROMP_CHECK(
      coverage.sorted_keys.empty() || (coverage.sorted_keys.size() == particles.count && coverage.left.size() == 1),
      "G2P's coverage check needs a block key per particle and one flag");
  if (return_map)
    for_each(exec, particles.count, GridToParticle<true>{particles, grid, step, coverage});
  else
    for_each(exec, particles.count, GridToParticle<false>{particles, grid, step, coverage});
}

void project_plasticity(const Exec& exec, const ParticleView& particles, const StepParams& step) {
  for_each(exec, particles.count, ProjectPlasticity{particles, step});
}

void record_non_finite_deformation(const Exec& exec, const ParticleView& particles, const StepParams& step,
                                   Stage stage) {
  for_each(exec, particles.count,
           RecordNonFiniteDeformation{Mat3Planes<const float>(particles.F), step.first_failure.subspan(int(stage), 1)});
}

float max_particle_speed(const Exec& exec, const ParticleView& particles, Span<float> slot) {
  ROMP_CHECK(slot.size() == 1, "max_particle_speed reduces into one element");
  memory::fill_zero(slot.data(), exec.backend, sizeof(float), exec.stream);
  for_each(exec, particles.count, MaxSpeed{Vec3Planes<const float>(particles.v), slot});
  return download(exec.backend, slot, exec.stream)[0];
}

}  // namespace romp::mpm
