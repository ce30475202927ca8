// The reduced-space pieces of the ROM's online step (ROM paper, Alg. 2, 6, 7): full-space velocities
// from the generalized velocity, and the least-squares normal equations that project full-space
// velocities or positions back onto the manifold.
#pragma once

#include <cstdint>

#include "kernels/core/exec.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/mpm/domain_walls.h"

namespace romp::rom {

// v_p = (∂g/∂x̂)(X_p) v̂ for n points: dg_dxhat holds 3 r planes of n (plane o r + j = ∂g_o/∂x̂_j, as
// evaluate_deformation_map writes them), vhat r values on exec's backend. With `live`, a count on exec's
// backend, only the first live[0] points.
void latent_to_point_velocity(const Exec& exec, int latent, Span<const float> dg_dxhat, Span<const float> vhat,
                              Vec3Planes<float> v, Span<const std::int64_t> live = {});

// The normal equations of min_y Σ_p ‖J_p y − (target_p − reference_p)‖² over m points, J_p = ∂g/∂x̂ at
// point p (3 r planes of m): `system` receives, in double, A = Σ J_pᵀ J_p (r × r, row-major), then
// c = Σ J_pᵀ (target_p − reference_p) (r), then the squared residual at y = 0, Σ ‖target_p − reference_p‖²
// (1): r² + r + 1 values on exec's backend. `reference` may be empty (taken as 0). Each entry sums its
// points in one fixed order, so the result does not depend on the backend's thread count.
void normal_equations(const Exec& exec, int latent, Span<const float> dg_dxhat, Vec3Planes<const float> target,
                      Vec3Planes<const float> reference, Span<double> system);

// The velocity projection's last step (ROM paper, Alg. 6–7) where its system is: solves the normal
// equations in `system` (normal_equations of the samples' trial velocities; A and c are overwritten by
// the Cholesky factor and the solution) for v̂_{n+1}, then x̂_{n+1} = x̂_n + dt v̂_{n+1}, in
// `latent` = [x̂ (r) | v̂ (r) | status (1)], r = `latent_size`. Status 0: solved; 1: the system is singular
// (x̂ and v̂ are left as they were). One thread: r is small; what it saves is the round trip of the system.
inline constexpr float kLatentSolved = 0.0f, kLatentSingular = 1.0f;
void advance_latent(const Exec& exec, int latent_size, Span<double> system, float dt, Span<float> latent);

// Lowers first[0] (set to kNoPointOutside beforehand) to the lowest index of the n points outside the band
// the full-order step keeps particles in (mpm::kept_inside_domain), a non-finite coordinate counting as
// outside, and moves each such point back into it as that step would. The reduced state decodes to points
// anywhere its map sends them: this is how a run finds that x̂ has left what the grid can hold without
// waiting for the answer, since the substep's later stages then see only positions the grid holds. The
// substep is rejected once the slot is read back, so the moved points' motion is never kept.
inline constexpr std::int64_t kNoPointOutside = INT64_MAX;
// With `live`, a count on exec's backend, only the first live[0] points are checked.
void keep_points_inside(const Exec& exec, Vec3Planes<float> x, const mpm::Domain& domain, float dx,
                        Span<std::int64_t> first, Span<const std::int64_t> live = {});

}  // namespace romp::rom
