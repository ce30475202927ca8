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
//   corners_to_particles  PIC/FLIP blend of Σ_α ω_αp v_α, F += Δt Σ_α v_α g_αpᵀ in the reference
//                         configuration (Eq. 7), x_p = Σ_α ω_αp x_α so a particle never leaves its domain.
// Because the weights are integrals over the undeformed domain, a flat or inverted domain causes no
// division by a vanishing current volume; neighbours stay attached through their shared corners.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/mpm/domain_init.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {

// What kernels see: per-domain weights (read only) and per-corner state and accumulators.
struct DomainView {
  Span<const std::int32_t> corner;      // [8 d + α]
  Span<const float> weight;             // [8 d + α]: ω_αp
  Vec3Planes<const float> gradient;     // entry 8 d + α: g_αp
  Index corners = 0;
  Vec3Planes<float> x;                  // corner positions
  Vec3Planes<float> v;                  // after grid_to_corners: grid velocity at the corner
  Vec3Planes<float> v_old;              // after grid_to_corners: the same before this substep's forces
  Span<float> mass;                     // accumulated by particles_to_corners
  Vec3Planes<float> momentum;
  Vec3Planes<float> force;
  Span<const std::int32_t> dirichlet_group;
};

class ParticleDomains {
 public:
  // Checks the description's sizes and corner indices; throws romp::Error naming what disagrees.
  ParticleDomains(Backend backend, const DomainInit& init);

  DomainView view();
  Index count() const { return count_; }
  Index corner_count() const { return corner_count_; }
  Vec3Planes<const float> corner_positions() const { return Vec3Planes<const float>(x_.data(), corner_count_); }
  std::vector<float> corner_positions_on_host(const Exec& exec) const { return x_.to_host(exec.stream); }
  std::size_t bytes() const;

 private:
  Index count_ = 0;
  Index corner_count_ = 0;
  DeviceBuffer<std::int32_t> corner_, dirichlet_group_;
  DeviceBuffer<float> weight_, gradient_;
  DeviceBuffer<float> x_, v_, v_old_, mass_, momentum_, force_;
};

// The stages, in pipeline order around update_grid. Only particles with a domain take part; the
// others go through particle_to_grid and grid_to_particle, into the same grid.
void particles_to_corners(const Exec& exec, const ParticleView& particles, const DomainView& domains,
                          const StepParams& step);
void corners_to_grid(const Exec& exec, const DomainView& domains, const GridView& grid, const StepParams& step);
void grid_to_corners(const Exec& exec, const DomainView& domains, const GridView& grid, const StepParams& step);
void corners_to_particles(const Exec& exec, const ParticleView& particles, const DomainView& domains,
                          const StepParams& step);

}  // namespace romp::mpm
