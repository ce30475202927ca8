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
// Constrained directions. The walls and colliders fix the velocity of some nodes along some
// directions (grid_boundary.h); there the velocity keeps its v* value and is not unknown: the
// operator is S A S with S_i = I − Σ q qᵀ the orthogonal projector of node i onto the directions
// left free (q an orthonormal basis of the held ones), and the held values enter through the
// initial residual S (M v* − A v*). Held are
//   - inside a sticky collider, the whole velocity; inside a slip or separating one, the direction
//     of its normal, unless v* separates from a separating collider. The tangential plane stays
//     unknown, also for an oblique normal (a sphere, a cylinder): held, it would be integrated
//     explicitly at an implicit step, which is unstable (ImplicitStep.CubeUnderASlipPlateStaysStable
//     goes non-finite when it is);
//   - on a sticky wall, the whole velocity; on a slip or separating wall, the normal direction when
//     v* does not move away from the wall (there the grid update removed the approach). A node that
//     separates from a wall is free: holding it would integrate its motion explicitly, which at an
//     implicit Δt is unstable. resolve_boundaries runs again after the solve, so a free node that the
//     solve turns towards the wall is stopped there like any other.
// Massless nodes are not unknowns either (no particle reads them): S = 0 there.
//
// Particles with domains (particle_domains.h) move their corners, and the corners follow the grid:
// a grid displacement x moves corner c by u_c = Σ_j w_j(x_c) x_j, changes the particle's F (updated
// in the reference configuration) by δF = Σ_α u_{c_α} g_αᵀ, and the force change at its corners,
// V⁰ δP g_α, reaches node j with the same weights: (K x)_j = Σ_c w_j(x_c) Σ_{(p, α): c_α = c} V⁰ δP_p g_α,
// again symmetric and semidefinite. Corners of Dirichlet groups follow their motion, not the grid,
// and take part in neither direction (as Dirichlet particles add no stiffness). Enriched corners
// (dynamic enrichment) are unknowns of their own beside the nodes (the paper's Eq. 12 over "grid
// nodes and enriched corners"): mass m_c (particles_to_corners), v* from corners_to_grid's
// explicit update, u_c their own entry instead of the interpolated grid displacement, and their
// force stays at the corner instead of reaching the grid. A transitional particle, with enriched and
// grid-bound corners, couples both kinds of unknowns; the operator stays symmetric and semidefinite
// because every unknown moves the particles' F through the same linear map that carries their
// forces back. Walls and colliders hold directions at an enriched corner by the same rule as at a node.
//
// Vectors are flat: 3 planes of ImplicitSystem::entries() values each, the grid's active nodes
// first, then one entry per domain corner (an unknown only while enriched, held otherwise); the
// projectors are 9 such planes.
#pragma once

#include "kernels/core/exec.h"
#include "kernels/core/span.h"
#include "kernels/material/material.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/mpm/particle_domains.h"
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
  Mat3Planes<const float> projector;                          // per node: S_i, onto the directions that are unknown
  DomainView domains;                                         // corners == 0 without particle domains
  Vec3Planes<float> corner_displacement, corner_force;        // scratch, one entry per corner

  ROMP_HD Index nodes() const { return grid.blocks * kNodesPerBlock; }
  // Values per component of the flat vectors: the active nodes, then the domain corners.
  ROMP_HD Index entries() const { return nodes() + domains.corners; }
};

// The semidefinite stiffness of each particle at its current (elastic) F; zero for Dirichlet particles.
void linearise_particles(const Exec& exec, const ParticleView& particles, const StepParams& step,
                         Span<material::PrincipalStiffness<float>> stiffness);

// The projector S_i of every entry as described above, from the masses and v* of the grid and of
// the enriched corners (load_explicit_velocities). `projector` holds nodes + corners entries.
void find_projectors(const Exec& exec, const GridView& grid, const DomainView& domains, const StepParams& step,
                     Mat3Planes<float> projector);

// The inverse of diag(M + Δt² K) on entries with mass, 0 on the others (Eq. 17-19 for MLS-MPM:
// K_ii,aa = Σ_p V⁰_p δF_a : δP(δF_a) with δF_a = e_a (F_pᵀ ∇w_ip)ᵀ).
void jacobi_inverse_diagonal(const Exec& exec, const ImplicitSystem& system, Span<float> inverse_diagonal);

// z = S D⁻¹ r: the Jacobi preconditioner S D⁻¹ S for r in the range of S (symmetric, and positive
// definite on that range, as preconditioned CG needs).
void apply_preconditioner(const Exec& exec, const ImplicitSystem& system, Span<const float> inverse_diagonal,
                          Span<const float> r, Span<float> z);

// Ax = S (M x + Δt² K x). x need not vanish along held directions: their values act on the free ones.
void apply_implicit_operator(const Exec& exec, const ImplicitSystem& system, Span<const float> x, Span<float> Ax);

// Mx = S M x, the right-hand side S M v* for x = v*.
void apply_mass(const Exec& exec, const ImplicitSystem& system, Span<const float> x, Span<float> Mx);

// v* into a flat vector: the grid's velocities after the grid update and the enriched corners'
// from corners_to_grid (the other corners' entries are held; they read 0).
void load_explicit_velocities(const Exec& exec, const ImplicitSystem& system, Span<float> v);

// The solution back to the grid and the enriched corners, each then through the walls and colliders
// of the grid update again (see above).
void store_velocities(const Exec& exec, const ImplicitSystem& system, Span<const float> v);

}  // namespace romp::mpm
