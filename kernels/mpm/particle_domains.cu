// ParticleDomains: upload and checks, and the particle → corner → grid → corner → particle stages.
#include "kernels/mpm/particle_domains.h"

#include <algorithm>
#include <limits>
#include <string>

#include "kernels/core/error.h"
#include "kernels/core/fill.h"
#include "kernels/core/for_each.h"
#include "kernels/core/memory.h"
#include "kernels/core/replace_value.h"
#include "kernels/material/material.h"
#include "kernels/material/stretch_clamp.h"
#include "kernels/material/volume.h"
#include "kernels/math/finite.h"
#include "kernels/math/scatter.h"
#include "kernels/mpm/bspline.h"
#include "kernels/mpm/grid_boundary.h"
#include "kernels/mpm/mls_transfer.h"
#include "kernels/mpm/stencil_nodes.h"
#include "kernels/svd/svd3.h"

namespace romp::mpm {
namespace {

struct MarkEnrichment {
  ParticleView particles;
  DomainView domains;
  StepParams step;
  float threshold;

  ROMP_HD void operator()(Index p) const {
    if (!particles.has_domain(p)) return;
    const float floor = step.materials[particles.material[p]].min_stretch;
    const Mat3<float> F = particles.F.load(p);
    bool enrich;
    if (material::stretches_surely_at_least(F, floor)) {
      // No stretch below the floor (so J > 0) and no SVD needed: ‖F⁻¹‖_F = ‖cof F‖_F / J.
      enrich = 3.0f * determinant(F) <=
               threshold * math::sqrt(squared_frobenius_norm(F) * squared_frobenius_norm(material::cofactor(F)));
    } else {
      // svd3 sorts the signed stretches: sigma[2] is the smallest.
      const Vec3<float> sigma = svd3(F).sigma;
      enrich = sigma[2] < floor || deformation_quality(sigma, math::max(floor, 1e-6f)) <= threshold;
    }
    if (!enrich) return;
    const Index d = particles.domain[p];
    for (int a = 0; a < kDomainCorners; ++a)
      atomic_max(&domains.enriched[domains.corner[kDomainCorners * d + a]], std::int32_t(1));
    atomic_add(&domains.enriched_particles[0], std::int32_t(1));
  }
};

struct ParticlesToCorners {
  ParticleView particles;
  DomainView domains;
  StepParams step;
  Scatter scatter;

  ROMP_HD void operator()(Index p) const {
    if (!particles.has_domain(p)) return;
    const Index d = particles.domain[p];
    const material::MaterialParams<float>& params = step.materials[particles.material[p]];
    const Mat3<float> F = particles.F.load(p);
    const Mat3<float> P = particle_first_piola(step, params, p, F);
    if (!is_finite(P)) atomic_min(&step.first_failure[int(Stage::P2G)], std::int64_t(p));
    atomic_max(&domains.stiffening[0], domain_stiffening(material::clamp_stretches(F, params.min_stretch)));
    const float mass = particles.mass[p];
    const Vec3<float> x = particles.x.load(p);
    const Vec3<float> momentum = mass * particles.v.load(p);
    Vec3<float> load_force = traction_force(step, particles, p);
    for (Index l = 0; l < step.loads.size(); ++l)
      if (step.loads[l].contains(x)) load_force += mass * step.loads[l].acceleration;
    const Mat3<float> volume_stress = particles.volume0[p] * P;
    for (int a = 0; a < kDomainCorners; ++a) {
      const Index entry = kDomainCorners * d + a;
      const Index c = domains.corner[entry];
      const float w = domains.weight[entry];
      scatter.add(&domains.mass[c], w * mass);
      scatter.add(domains.momentum, c, w * momentum);
      scatter.add(domains.force, c, w * load_force - volume_stress * domains.gradient.load(entry));
    }
  }
};

// kActiveNodesOnly: the grid holds only some of the corners' stencil blocks (a reduced step's grid of its
// samples' corners), the others' shares are dropped, and it may keep no velocity before forces.
template <bool kActiveNodesOnly>
struct CornersToGrid {
  DomainView domains;
  GridView grid;
  StepParams step;
  Scatter scatter;

  ROMP_HD void operator()(Index c) const {
    const float mass = domains.mass[c];
    const Vec3<float> momentum = domains.momentum.load(c);
    const Vec3<float> impulse = momentum + step.dt * domains.force.load(c);
    if (domains.enriched[c]) {
      // A degree of freedom of its own: explicit Euler on its mass, momentum and force (Eq. 13 at the
      // corner), then the boundaries, as the grid update does for nodes. The implicit step takes this
      // v as its v* and replaces it; grid_to_corners reads it.
      if (domains.dirichlet_group[c] != kNoDirichletGroup) return;  // grid_to_corners moves it rigidly
      const float inverse_mass = 1.0f / mass;
      domains.v_old.store(c, inverse_mass * momentum);
      const NodeVelocity<float> corner(impulse, inverse_mass, step.dt, step.gravity);
      domains.v.store(c, resolve_boundaries(step, domains.x.load(c), grid.dx, corner.free));
      return;
    }
    const QuadraticStencil<float> stencil(domains.x.load(c), grid.inverse_dx);
    const StencilNodes nodes(stencil, grid.table);
    const bool flip = !kActiveNodesOnly || grid.keeps_old_velocity();
    for_each_stencil_offset([&](int i, int j, int k) {
      if (kActiveNodesOnly && !nodes.active(i, j, k)) return;
      const float w = stencil.weight(i, j, k);
      const Index n = nodes.node(i, j, k);
      scatter.add(&grid.mass[n], w * mass);
      scatter.add(grid.velocity, n, w * impulse);
      if (flip) scatter.add(grid.velocity_old, n, w * momentum);
    });
  }
};

struct GridToCorners {
  DomainView domains;
  GridView grid;
  StepParams step;

  ROMP_HD void operator()(Index c) const {
    const Vec3<float> start = domains.x.load(c);
    Vec3<float> v = Vec3<float>::zero(), v_old = Vec3<float>::zero();
    // The displacement is kept apart from the position: x_new − x_old would lose most of its digits
    // to cancellation (a step moves a corner by far less than its coordinates).
    Vec3<float> moved;
    const std::int32_t group = domains.dirichlet_group[c];
    if (group != kNoDirichletGroup) {
      const RigidMotion& motion = step.dirichlet[group];
      v = v_old = motion.velocity_at(start);
      moved = motion.displacement(start, step.dt);
    } else {
      if (domains.enriched[c]) {
        // Integrated on its own by corners_to_grid (and the implicit solve, if any).
        v = domains.v.load(c);
        v_old = domains.v_old.load(c);
      } else {
        const QuadraticStencil<float> stencil(start, grid.inverse_dx);
        const StencilNodes nodes(stencil, grid.table);
        for_each_stencil_offset([&](int i, int j, int k) {
          const float w = stencil.weight(i, j, k);
          const Index n = nodes.node(i, j, k);
          v += w * grid.velocity.load(n);
          v_old += w * grid.velocity_old.load(n);
        });
      }
      moved = step.dt * v;
      // A corner that would end up inside a collider stops on its surface, along the normal (Zhu et
      // al., Sec. 7, after Stomakhin et al. 2013), so domains never reach into a collider.
      for (Index k = 0; k < step.colliders.size(); ++k) {
        const SignedDistance sd = signed_distance(step.colliders[k], start + moved);
        if (sd.distance < 0.0f) moved -= sd.distance * sd.normal;
      }
    }
    // Keep the corner's stencil inside the domain, as grid_to_particle does for particles.
    const Vec3<float> target = start + moved, kept = kept_inside_domain(step.domain, target, grid.dx);
    for (int a = 0; a < 3; ++a)
      if (kept[a] != target[a]) moved[a] = kept[a] - start[a];
    domains.x.store(c, start + moved);
    domains.v.store(c, v);
    domains.v_old.store(c, v_old);
    domains.moved.store(c, moved);
  }
};

struct CornersToParticles {
  ParticleView particles;
  DomainView domains;
  StepParams step;

  ROMP_HD void operator()(Index p) const {
    if (!particles.has_domain(p)) return;
    const Index d = particles.domain[p];
    Vec3<float> x = particles.x.load(p);
    Vec3<float> v;
    Mat3<float> C;
    Mat3<float> F = particles.F.load(p);
    const std::int32_t group = particles.dirichlet_group[p];
    if (group != kNoDirichletGroup) {
      step.dirichlet[group].carry(step.dt, x, v, C, F);
    } else {
      Vec3<float> v_pic = Vec3<float>::zero(), dv_flip = Vec3<float>::zero();
      Mat3<float> displacement_gradient = Mat3<float>::zero();  // ∇_X Δx, in the reference configuration
      x = Vec3<float>::zero();
      for_each_domain_corner(domains, d, [&](Index c, float w, const Vec3<float>& gradient) {
        const Vec3<float> v_corner = domains.v.load(c);
        v_pic += w * v_corner;
        dv_flip += w * (v_corner - domains.v_old.load(c));
        displacement_gradient += Mat3<float>::outer(domains.moved.load(c), gradient);
        x += w * domains.x.load(c);
      });
      v = step.flip_alpha * (particles.v.load(p) + dv_flip) + (1.0f - step.flip_alpha) * v_pic;
      // C is the spatial velocity gradient ∇_X Δx F⁻¹ / Δt (what outputs report); a flat domain has none.
      const float J = determinant(F);
      C = math::abs(J) > 1e-12f ? (1.0f / (J * step.dt)) * times_transpose(displacement_gradient, material::cofactor(F))
                                : Mat3<float>::zero();
      F += displacement_gradient;
    }
    store_moved_particle(particles, step, p, x, v, C, F);
  }
};

struct ReleaseDomains {
  ParticleView particles;
  Region region;
  ROMP_HD void operator()(Index p) const {
    if (particles.has_domain(p) && region.contains(particles.x.load(p))) particles.domain[p] = kNoDomain;
  }
};

}  // namespace

void release_domains(const Exec& exec, const ParticleView& particles, const Region& region) {
  if (!particles.domain.empty()) for_each(exec, particles.count, ReleaseDomains{particles, region});
}

ParticleDomains::ParticleDomains(Backend backend, const DomainInit& init)
    : count_(init.count()), corner_count_(init.corner_count()) {
  const Index entries = kDomainCorners * count_;
  using std::to_string;
  ROMP_CHECK(Index(init.corner.size()) == entries && Index(init.weight.size()) == entries &&
                 Index(init.gradient.size()) == 3 * entries,
             "particle domains: " + to_string(count_) + " domains need " + to_string(entries) +
                 " corner indices and weights and " + to_string(3 * entries) + " gradient entries");
  ROMP_CHECK(Index(init.corner_x.size()) == 3 * corner_count_,
             "particle domains: " + to_string(corner_count_) + " corners need " + to_string(3 * corner_count_) +
                 " position entries, got " + to_string(init.corner_x.size()));
  for (Index e = 0; e < entries; ++e) {
    const std::int32_t c = init.corner[std::size_t(e)];
    ROMP_CHECK(c >= 0 && c < corner_count_, "particle domains: domain " + to_string(e / kDomainCorners) +
                                                " names corner " + to_string(c) + ", outside [0, " +
                                                to_string(corner_count_) + ")");
  }
  corner_ = DeviceBuffer<std::int32_t>::from_host(backend, init.corner);
  dirichlet_group_ = DeviceBuffer<std::int32_t>::from_host(backend, init.corner_dirichlet_group);
  weight_ = DeviceBuffer<float>::from_host(backend, init.weight);
  std::vector<float> gradient_planes(std::size_t(3 * entries));
  for (Index e = 0; e < entries; ++e)
    for (int a = 0; a < 3; ++a) gradient_planes[std::size_t(a * entries + e)] = init.gradient[std::size_t(3 * e + a)];
  gradient_ = DeviceBuffer<float>::from_host(backend, gradient_planes);
  ROMP_CHECK(init.resumed_corner_x.empty() || init.resumed_corner_x.size() == init.corner_x.size(),
             "particle domains: resumed corner positions for " + to_string(init.resumed_corner_x.size() / 3) +
                 " corners, the domains have " + to_string(corner_count_));
  x_ = DeviceBuffer<float>::from_host(backend, init.resumed_corner_x.empty() ? init.corner_x : init.resumed_corner_x);
  for (DeviceBuffer<float>* planes : {&v_, &v_old_, &moved_, &momentum_, &force_}) {
    *planes = DeviceBuffer<float>(backend, 3 * corner_count_);
    planes->fill_zero();
  }
  mass_ = DeviceBuffer<float>(backend, corner_count_);
  mass_.fill_zero();
  enriched_ = DeviceBuffer<std::int32_t>(backend, corner_count_);
  enriched_.fill_zero();
  enriched_particles_ = DeviceBuffer<std::int32_t>(backend, 1);
  enriched_particles_.fill_zero();
  ROMP_CHECK(init.stiffening >= 1.0f,
             "particle domains: the initial stiffening must be >= 1, got " + std::to_string(init.stiffening));
  stiffening_ = DeviceBuffer<float>::from_host(backend, std::vector<float>{init.stiffening});
  double smallest_edge = std::numeric_limits<double>::infinity();
  for (Index d = 0; d < count_; ++d)
    // Corner 0's three neighbours along the reference axes (α = 4, 2, 1).
    for (int a : {4, 2, 1})
      smallest_edge = std::min(
          smallest_edge, norm(init.corner_position(init.corner_x, d, a) - init.corner_position(init.corner_x, d, 0)));
  smallest_edge_ = float(smallest_edge);
}

void ParticleDomains::release_dirichlet_group(const Exec& exec, std::int32_t group) {
  for_each(exec, corner_count_, ReplaceValue<std::int32_t>{dirichlet_group_.span(), group, kNoDirichletGroup});
}

float ParticleDomains::stiffening(const Exec& exec) const { return stiffening_.to_host(exec.stream)[0]; }

double ParticleDomains::enriched_share(const Exec& exec) const {
  return count_ == 0 ? 0.0 : double(enriched_particles_.to_host(exec.stream)[0]) / double(count_);
}

DomainView ParticleDomains::view() {
  const Index n = corner_count_;
  return DomainView{corner_.span(),
                    weight_.span(),
                    Vec3Planes<const float>(gradient_.data(), kDomainCorners * count_),
                    n,
                    Vec3Planes<float>(x_.data(), n),
                    Vec3Planes<float>(v_.data(), n),
                    Vec3Planes<float>(v_old_.data(), n),
                    Vec3Planes<float>(moved_.data(), n),
                    mass_.span(),
                    Vec3Planes<float>(momentum_.data(), n),
                    Vec3Planes<float>(force_.data(), n),
                    dirichlet_group_.span(),
                    enriched_.span(),
                    enriched_particles_.span(),
                    stiffening_.span()};
}

std::size_t ParticleDomains::bytes() const {
  return corner_.bytes() + dirichlet_group_.bytes() + weight_.bytes() + gradient_.bytes() + x_.bytes() + v_.bytes() +
         v_old_.bytes() + moved_.bytes() + mass_.bytes() + momentum_.bytes() + force_.bytes() + enriched_.bytes() +
         enriched_particles_.bytes() + stiffening_.bytes();
}

void mark_enrichment(const Exec& exec, const ParticleView& particles, const DomainView& domains, const StepParams& step,
                     float threshold) {
  memory::fill_zero(domains.enriched.data(), exec.backend, std::size_t(domains.corners) * sizeof(std::int32_t),
                    exec.stream);
  memory::fill_zero(domains.enriched_particles.data(), exec.backend, sizeof(std::int32_t), exec.stream);
  if (threshold > 0.0f) for_each(exec, particles.count, MarkEnrichment{particles, domains, step, threshold});
}

void particles_to_corners(const Exec& exec, const ParticleView& particles, const DomainView& domains,
                          const StepParams& step) {
  const std::size_t bytes = std::size_t(domains.corners) * sizeof(float);
  memory::fill_zero(domains.mass.data(), exec.backend, bytes, exec.stream);
  for (int a = 0; a < 3; ++a) {
    memory::fill_zero(domains.momentum.data() + a * domains.corners, exec.backend, bytes, exec.stream);
    memory::fill_zero(domains.force.data() + a * domains.corners, exec.backend, bytes, exec.stream);
  }
  fill(exec, domains.stiffening.subspan(0, 1), 1.0f);  // at rest
  for_each(exec, particles.count, ParticlesToCorners{particles, domains, step, Scatter::for_exec(exec)});
}

void corners_to_grid(const Exec& exec, const DomainView& domains, const GridView& grid, const StepParams& step) {
  ROMP_CHECK(grid.keeps_old_velocity(), "corners_to_grid needs a grid that keeps the velocity before forces (FLIP)");
  for_each(exec, domains.corners, CornersToGrid<false>{domains, grid, step, Scatter::for_exec(exec)});
}

void corners_to_active_nodes(const Exec& exec, const DomainView& domains, const GridView& grid,
                             const StepParams& step) {
  for_each(exec, domains.corners, CornersToGrid<true>{domains, grid, step, Scatter::for_exec(exec)});
}

void grid_to_corners(const Exec& exec, const DomainView& domains, const GridView& grid, const StepParams& step) {
  for_each(exec, domains.corners, GridToCorners{domains, grid, step});
}

void corners_to_particles(const Exec& exec, const ParticleView& particles, const DomainView& domains,
                          const StepParams& step) {
  for_each(exec, particles.count, CornersToParticles{particles, domains, step});
}

}  // namespace romp::mpm
