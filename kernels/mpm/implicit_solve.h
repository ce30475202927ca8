// The grid operator of the implicit MLS-MPM step, matrix-free: A = M + Δt² K, its Jacobi diagonal,
// and which velocity components are unknowns. The CG that solves A v = M v* drives these from the
// host (host/implicit_grid_solver.h).
//
// Linearisation (enriched-MPM paper, Sec. 6, Eq. 12-15, written for MLS-MPM on quadratic B-splines
// in the spatial frame). MLS-MPM moves F with the grid velocities as F_p' = (I + Δt Σ_j v_j ∇w_jpᵀ) F_p,
// ∇w_jp = w_jp D⁻¹ (x_j − x_p), D⁻¹ = 4/dx² (bspline.h); that is the velocity gradient C = B D⁻¹ of
// g2p.cu. The elastic energy of the grid moved to x̂_j = x_j + u_j is Φ(u) = Σ_p V⁰_p ψ(F̂_p),
// F̂_p = (I + Σ_j u_j ∇w_jpᵀ) F_p, so
//   f_i = −∂Φ/∂u_i = −Σ_p V⁰_p P(F̂_p) F_pᵀ ∇w_ip,
// which at u = 0 is the explicit force of P2G (the affine impulse −Δt V⁰ D⁻¹ P Fᵀ applied through
// (x_i − x_p)). One Newton step of backward Euler, u = Δt v, linearised at u = 0, gives Eq. (12)
//   (M + Δt² K) v = M v*,   K δu = −∂f/∂u δu,
// with v* the explicit grid velocity (Eq. 13: P2G's momentum, gravity, walls and colliders), and
//   δF_p = Σ_j δu_j ∇w_jpᵀ F_p,   (K δu)_i = Σ_p V⁰_p δP(F_p; δF_p) F_pᵀ ∇w_ip      (Eq. 14-15).
// K is symmetric: δu'ᵀ K δu = Σ_p V⁰_p δF'_p : δP(δF_p), and δP is the action of a symmetric
// 9x9 stiffness. It is semidefinite once δP uses the semidefinite principal stiffness of Teran et
// al. 2005 (PrincipalStiffness::definite, Eq. 16), so A = M + Δt² K is positive definite on the
// nodes that carry mass, and CG applies. Particles of Dirichlet groups add no stiffness: G2P
// prescribes their F, so it does not depend on the grid velocities.
//
// Constrained components. The walls and colliders fix some velocity components of v* (grid_boundary.h);
// those are held at their v* value and are not unknowns: the operator is S A S, with S the 0/1
// diagonal `free`, and the held values enter through the initial residual S (M v* − A v*). Held are
//   - inside a sticky collider, every component; inside a slip or separating one, the components
//     along which its normal has a share above 0.1 (S stays diagonal: an axis-aligned normal's
//     component exactly, an oblique normal's two or three), unless v* separates from a separating
//     collider. Tangential components stay unknowns, for the reason below;
//   - on a sticky wall, every component; on a slip or separating wall, the normal component when v*
//     does not move away from the wall (there the grid update removed the approach). A node that
//     separates from a wall is free: holding it would integrate its motion explicitly, which at an
//     implicit Δt is unstable. resolve_boundaries runs again after the solve, so a free node that the
//     solve turns towards the wall is stopped there like any other.
// Massless nodes are not unknowns either (no particle reads them).
//
// Vectors are flat: 3 planes of the grid's active nodes (stride grid.blocks · kNodesPerBlock).
#pragma once

#include "kernels/core/exec.h"
#include "kernels/core/span.h"
#include "kernels/material/material.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {

// Everything the operator of one substep reads.
struct ImplicitSystem {
  ParticleView particles;
  GridView grid;  // mass, and v* in `velocity`
  StepParams step;
  Span<const material::PrincipalStiffness<float>> stiffness;  // per particle, at its F
  Span<const float> free;  // per node and component: 1 for an unknown, 0 where held
};

// The semidefinite stiffness of each particle at its current (elastic) F; zero for Dirichlet particles.
void linearise_particles(const Exec& exec, const ParticleView& particles, const StepParams& step,
                         Span<material::PrincipalStiffness<float>> stiffness);

// `free` (3 planes of active nodes) as described above, from the grid's mass and v*.
void find_free_components(const Exec& exec, const GridView& grid, const StepParams& step, Span<float> free);

// The inverse of diag(M + Δt² K) on free components, 0 on held ones (Eq. 17-19 for MLS-MPM:
// K_ii,aa = Σ_p V⁰_p δF_a : δP(δF_a) with δF_a = e_a (F_pᵀ ∇w_ip)ᵀ).
void jacobi_inverse_diagonal(const Exec& exec, const ImplicitSystem& system, Span<float> inverse_diagonal);

// Ax = S (M x + Δt² K x). x need not vanish on held components: their values act on the free ones.
void apply_implicit_operator(const Exec& exec, const ImplicitSystem& system, Span<const float> x, Span<float> Ax);

// Mx = S M x, the right-hand side S M v* for x = v*.
void apply_mass(const Exec& exec, const ImplicitSystem& system, Span<const float> x, Span<float> Mx);

// Runs the walls and colliders of the grid update again on the grid's velocities (see above).
void resolve_grid_boundaries(const Exec& exec, const GridView& grid, const StepParams& step);

}  // namespace romp::mpm
