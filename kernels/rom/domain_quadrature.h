// The reduced step on particle domains: the kinematics and transfers of the enriched-MPM paper's domains
// (kernels/mpm/particle_domains.h) with the corners placed by the deformation map, so that a model trained
// on particle-domain snapshots is run with the discretisation that made them.
//
// The full-order domain step moves a particle through its domain's 8 corners: mass, momentum and the
// stress's force −V⁰ P g_αp go particle → corners → grid, velocities grid → corners → particle, and F is
// the gradient of the corners' trilinear interpolation in the reference configuration. Decoded from g, the
// corners sit at x_α = g(X_α; x̂) with v_α = (∂g/∂x̂)(X_α) v̂, and a domain's particle follows them as that
// step leaves it. At large stretches (the torsion scene's fourfold length) the corners' shared FE-like
// forces are what keeps the grid's velocities those of the data; a particle's own stencil would not.
#pragma once

#include <cstdint>

#include "kernels/core/exec.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/mpm/particle_domains.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/step.h"

namespace romp::rom {

// Every domain point's kinematics from its corners' (domains.x, domains.v), as the full-order step leaves
// a domain's particle: x_p = Σ_α ω_αp x_α, v_p = Σ_α ω_αp v_α, F_p = Σ_α x_α g_αpᵀ, C_p = 0 (the reduced
// step's transfer is PIC). Every point must have a domain.
void points_from_corners(const Exec& exec, const mpm::ParticleView& points, const mpm::DomainView& domains);

// The corners of the samples' domains, corner α of sample s at 8 s + α of `corners` (8 m points): the
// points whose stencils G2P at the samples reads, so the samples' grid is built from them. `sample_point`:
// each sample's material point; `point_domain`: each material point's domain.
void gather_sample_corners(const Exec& exec, Span<const std::int32_t> sample_point,
                           Span<const std::int32_t> point_domain, const mpm::DomainView& domains,
                           Vec3Planes<float> corners);

// G2P at samples with domains, as grid_to_corners then corners_to_particles with PIC: v_s = Σ_α ω_αs v_α over
// the corners gather_sample_corners placed, v_α = Σ_i w_i(x_α) v_i, or the rigid motion at a corner of a
// Dirichlet group, or an enriched corner's own (corners_to_active_nodes wrote it); then x_s += Δt v_s (kept
// inside the domain), C_s = 0 and F_s as it was; a sample of a Dirichlet group moves rigidly. Records G2P's failure and
// the samples' largest speed as grid_to_particle does.
void grid_to_domain_samples(const Exec& exec, const mpm::ParticleView& samples, Span<const std::int32_t> sample_point,
                            Span<const std::int32_t> point_domain, const mpm::DomainView& domains,
                            Vec3Planes<const float> corners, const mpm::GridView& grid, const mpm::StepParams& step);

}  // namespace romp::rom
