// ImplicitGridSolver: the implicit step's velocity solve, (M + Δt² K) v = M v* (one Newton step of
// backward Euler, enriched-MPM paper Eq. 12), by Jacobi-preconditioned CG on the matrix-free operator
// of kernels/mpm/implicit_solve.h. Owns the solver's vectors, reused from substep to substep.
#pragma once

#include <cstdint>

#include "host/engine/sim_config.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/core/vector_ops.h"
#include "kernels/material/material.h"
#include "kernels/mpm/particle_domains.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/step.h"

namespace romp::engine {

struct ImplicitSolveReport {
  bool converged = false;
  std::int32_t iterations = 0;
  double relative_residual = 0.0;  // ‖r‖ over the convergence reference (see solve)
};

// Counts over a run, for diagnostics.
struct ImplicitSolveTotals {
  std::int64_t solves = 0;
  std::int64_t not_converged = 0;
  std::int64_t iterations = 0;  // CG iterations over all solves
  std::int32_t most_iterations = 0;
};

class ImplicitGridSolver {
 public:
  ImplicitGridSolver(Backend backend, ImplicitSolverConfig config);

  // Replaces the velocities v* of the grid (after the grid update) and of the enriched domain
  // corners (after corners_to_grid) by v, the solution on the free components (implicit_solve.h)
  // with the held ones kept at v*, then applies the walls and colliders again. CG starts from v*
  // and has converged when ‖r‖ ≤ tolerance · max(‖S M v*‖, ‖r₀‖) (the initial residual stands in
  // when no momentum sits on the unknowns, e.g. a body at rest beside a moving collider). When it
  // has not converged after max_iterations, or breaks down, the grid keeps v*, and a warning names
  // `step`, the substep being computed. `domains` has corners == 0 when there are none.
  ImplicitSolveReport solve(const Exec& exec, const mpm::ParticleView& particles, const mpm::DomainView& domains,
                            const mpm::GridView& grid, const mpm::StepParams& step, std::int64_t step_number);

  const ImplicitSolveTotals& totals() const { return totals_; }

 private:
  void reserve(Index particles, Index unknowns, Index corners);

  Backend backend_;
  ImplicitSolverConfig config_;
  DeviceBuffer<material::PrincipalStiffness<float>> stiffness_;
  // 3 planes of active nodes and domain corners each: iterate, residual, preconditioned residual,
  // search direction, operator times direction and inverse diagonal; 9 planes: the projectors.
  DeviceBuffer<float> x_, r_, z_, p_, q_, inverse_diagonal_, projector_;
  DeviceBuffer<float> corner_displacement_, corner_force_;  // 3 planes of domain corners each
  DotProduct dot_;
  ImplicitSolveTotals totals_;
};

}  // namespace romp::engine
