// ParticleDomains: hexahedral particle domains with shared corners, and the four transfer stages
// that carry their particles to the grid and back through the corners.
//
// Enriched MPM (Zhu et al., Sec. 4, Eq. 4–9), on romp's quadratic B-spline grid:
//   particles_to_corners  corner mass m_α = Σ_p ω_αp m_p, momentum Σ_p ω_αp m_p v_p and force
//                         f_α = −Σ_p V⁰_p P_p g_αp (Eq. 8 split at the corners), plus load impulses;
//   corners_to_grid       the corners rasterise with the grid weights ω_i(x_α);
//   (update_grid)         as for every particle;
//   grid_to_corners       v_α = Σ_i ω_i(x_α) v_i (and before forces, for FLIP), x_α += Δt v_α (Eq. 9);
//                         corners of a Dirichlet group follow its rigid motion;
//   corners_to_particles  PIC/FLIP blend of Σ_α ω_αp v_α, F += Σ_α Δx_α g_αpᵀ in the reference
//                         configuration (Eq. 7 with the corners' actual displacements Δx_α, which are
//                         Δt v_α except where a collider or the domain margin moved a corner: F then
//                         stays the gradient of the corner positions), x_p = Σ_α ω_αp x_α so a particle
//                         never leaves its domain.
// Dynamic enrichment (Sec. 5): mark_enrichment flags the corners of badly deformed particles first;
// corners_to_grid does not rasterise those but integrates them as degrees of freedom of their own
// (v = (p + Δt f)/m + Δt g, walls and colliders applied at the corner; the implicit step then
// solves for them with the grid), and grid_to_corners moves them with that velocity, the
// interpolation inside the domain being exact in material space. Particles with some flagged
// corners are transitional and reach both. Flags are recomputed every substep, so corners return to
// the grid when the metric recovers.
// Because the weights are integrals over the undeformed domain, a flat or inverted domain causes no
// division by a vanishing current volume; neighbours stay attached through their shared corners.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/material/volume.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/math/scalar.h"
#include "kernels/mpm/domain_init.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {

// What kernels see: per-domain weights (read only) and per-corner state and accumulators.
struct DomainView {
  Span<const std::int32_t> corner;   // [8 d + α]
  Span<const float> weight;          // [8 d + α]: ω_αp
  Vec3Planes<const float> gradient;  // entry 8 d + α: g_αp
  Index corners = 0;
  Vec3Planes<float> x;      // corner positions
  Vec3Planes<float> v;      // after grid_to_corners: grid velocity at the corner
  Vec3Planes<float> v_old;  // after grid_to_corners: the same before this substep's forces
  Vec3Planes<float> moved;  // after grid_to_corners: the corner's displacement this substep
  Span<float> mass;         // accumulated by particles_to_corners
  Vec3Planes<float> momentum;
  Vec3Planes<float> force;
  Span<const std::int32_t> dirichlet_group;
  Span<std::int32_t> enriched;            // per corner: 1 when it is a degree of freedom of its own this substep
  Span<std::int32_t> enriched_particles;  // [0]: particles that flagged their corners this substep
  Span<float> stiffening;                 // [0]: domain_stiffening of this substep's particles
};

// Visits the 8 corners of domain d as visit(corner index, ω_αd, g_αd), α in order.
template <class Visit>
ROMP_HD_INLINE void for_each_domain_corner(const DomainView& domains, Index d, const Visit& visit) {
  for (int a = 0; a < kDomainCorners; ++a) {
    const Index entry = kDomainCorners * d + a;
    visit(Index(domains.corner[entry]), domains.weight[entry], domains.gradient.load(entry));
  }
}

// How much the squared elastic wave speed of a particle at F may exceed its value at rest, an
// estimate without an SVD: max(1, ‖F̃‖²/3, ‖cof F̃‖²/3), F̃ with the inversion clamp. Stiffness grows
// with deformation (fixed corotated's volumetric term is λ ‖∂J/∂F‖² = λ ‖cof F‖²), and enriched
// corners, integrated explicitly like a hexahedral mesh, go unstable when the step only respects
// the wave speed at rest (seen while developing: the stability case of a cube forced through itself,
// enriched, E = 1e5, gained energy without bound after release at cfl 0.5 and was stable at cfl 0.1).
template <class T>
ROMP_HD_INLINE T domain_stiffening(const Mat3<T>& F_clamped) {
  const T by_stretch = squared_frobenius_norm(F_clamped) / T(3);
  const T by_volume = squared_frobenius_norm(material::cofactor(F_clamped)) / T(3);
  return math::max(T(1), math::max(by_stretch, by_volume));
}

// Zhu et al.'s metric, normalised to (0, 1]: K(F) = 3 / (‖F‖_F ‖F⁻¹‖_F), 1 for every rotation and
// smaller the more F distorts. (The paper's Eq. 10 omits the 3, whose K would be at most 1/3 and
// below its threshold 0.6 at rest; it states K in [0, 1].) F's stretches are taken at least
// `floor` (the inversion clamp), so flat and inverted F have a finite metric.
template <class T>
ROMP_HD_INLINE T deformation_quality(const Vec3<T>& sigma, T floor) {
  T squares = T(0), inverse_squares = T(0);
  for (int i = 0; i < 3; ++i) {
    const T s = math::max(sigma[i], floor);
    squares += s * s;
    inverse_squares += T(1) / (s * s);
  }
  return T(3) / math::sqrt(squares * inverse_squares);
}

class ParticleDomains {
 public:
  // Checks the description's sizes and corner indices; throws romp::Error naming what disagrees.
  ParticleDomains(Backend backend, const DomainInit& init);

  DomainView view();
  Index count() const { return count_; }
  Index corner_count() const { return corner_count_; }
  Vec3Planes<const float> corner_positions() const { return Vec3Planes<const float>(x_.data(), corner_count_); }
  // The shortest edge of a reference domain: the element size that bounds the explicit step while
  // corners are enriched.
  float smallest_edge() const { return smallest_edge_; }
  // The share of domain particles that enriched their corners in the last substep (a host sync).
  double enriched_share(const Exec& exec) const;
  // The largest domain_stiffening in the last substep, 1 before the first (a host sync).
  float stiffening(const Exec& exec) const;
  std::vector<float> corner_positions_on_host(const Exec& exec) const { return x_.to_host(exec.stream); }
  // The 8 corner indices of every domain (DomainInit::corner).
  std::vector<std::int32_t> corner_indices_on_host(const Exec& exec) const { return corner_.to_host(exec.stream); }
  // The corners' velocities after the last substep's grid_to_corners (3 planes).
  std::vector<float> corner_velocities_on_host(const Exec& exec) const { return v_.to_host(exec.stream); }
  std::size_t bytes() const;
  // The corners that followed Dirichlet group `group` move freely from now on.
  void release_dirichlet_group(const Exec& exec, std::int32_t group);

 private:
  Index count_ = 0;
  Index corner_count_ = 0;
  float smallest_edge_ = 0.0f;
  DeviceBuffer<std::int32_t> corner_, dirichlet_group_, enriched_, enriched_particles_;
  DeviceBuffer<float> stiffening_;
  DeviceBuffer<float> weight_, gradient_;
  DeviceBuffer<float> x_, v_, v_old_, moved_, mass_, momentum_, force_;
};

// Flags the corners of every domain particle whose deformation_quality is at most `threshold`, or
// one of whose stretches is below its material's inversion clamp (min_stretch). threshold 0: none.
void mark_enrichment(const Exec& exec, const ParticleView& particles, const DomainView& domains, const StepParams& step,
                     float threshold);

// Takes the domain away from every particle inside `region` (for good): from now on it exchanges
// with the grid through its own stencil, like a particle that never had one, so the material can
// separate there (the enriched-MPM paper disables domains "if topological changes are required").
// Its corners stay, shared with the neighbours that keep theirs.
void release_domains(const Exec& exec, const ParticleView& particles, const Region& region);

// The stages, in pipeline order around update_grid. Only particles with a domain take part; the
// others go through particle_to_grid and grid_to_particle, into the same grid.
void particles_to_corners(const Exec& exec, const ParticleView& particles, const DomainView& domains,
                          const StepParams& step);
void corners_to_grid(const Exec& exec, const DomainView& domains, const GridView& grid, const StepParams& step);
// corners_to_grid into a grid that holds only some of the corners' stencils (a reduced step's, built around
// its samples): the shares of nodes outside it are dropped, and the velocity before forces is kept only where
// the grid keeps it. Enriched corners integrate on their own, as there.
void corners_to_active_nodes(const Exec& exec, const DomainView& domains, const GridView& grid, const StepParams& step);
void grid_to_corners(const Exec& exec, const DomainView& domains, const GridView& grid, const StepParams& step);
void corners_to_particles(const Exec& exec, const ParticleView& particles, const DomainView& domains,
                          const StepParams& step);

}  // namespace romp::mpm
