// ImplicitGridSolver: preconditioned CG (Shewchuk 1994, "An introduction to the conjugate gradient
// method without the agonizing pain", B3) over the kernels of implicit_solve.h.
#include "host/engine/implicit_grid_solver.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "kernels/core/error.h"
#include "kernels/core/memory.h"
#include "kernels/mpm/implicit_solve.h"

namespace romp::engine {
namespace {

// Grows `buffer` to hold at least `size` elements, with slack so a grid that gains a few blocks
// does not reallocate every substep.
template <class T>
void ensure_size(DeviceBuffer<T>& buffer, Backend backend, Index size) {
  if (buffer.size() < size) buffer = DeviceBuffer<T>(backend, size + size / 2);
}

}  // namespace

ImplicitGridSolver::ImplicitGridSolver(Backend backend, ImplicitSolverConfig config)
    : backend_(backend), config_(config), dot_(backend) {
  ROMP_CHECK(config_.tolerance > 0.0f && config_.max_iterations >= 1,
             fmt::format("the implicit solve needs a tolerance > 0 and at least one CG iteration, got {} and {}",
                         config_.tolerance, config_.max_iterations));
}

void ImplicitGridSolver::reserve(Index particles, Index unknowns, Index corners) {
  for (DeviceBuffer<float>* corner_vector : {&corner_displacement_, &corner_force_})
    ensure_size(*corner_vector, backend_, 3 * corners);
  ensure_size(stiffness_, backend_, particles);
  for (DeviceBuffer<float>* vector : {&x_, &r_, &z_, &p_, &q_, &inverse_diagonal_})
    ensure_size(*vector, backend_, unknowns);
  ensure_size(projector_, backend_, 3 * unknowns);  // 9 planes of nodes
}

ImplicitSolveReport ImplicitGridSolver::solve(const Exec& exec, const mpm::ParticleView& particles,
                                              const mpm::DomainView& domains, const mpm::GridView& grid,
                                              const mpm::StepParams& step, std::int64_t step_number) {
  const Index unknowns = 3 * (grid.blocks * mpm::kNodesPerBlock + domains.corners);
  reserve(particles.count, unknowns, domains.corners);
  const Span<float> x = x_.span().subspan(0, unknowns), r = r_.span().subspan(0, unknowns),
                    z = z_.span().subspan(0, unknowns), p = p_.span().subspan(0, unknowns),
                    q = q_.span().subspan(0, unknowns),
                    inverse_diagonal = inverse_diagonal_.span().subspan(0, unknowns);
  const Mat3Planes<float> projector(projector_.data(), unknowns / 3);
  const Span<material::PrincipalStiffness<float>> stiffness = stiffness_.span().subspan(0, particles.count);

  mpm::linearise_particles(exec, particles, step, stiffness);
  mpm::find_projectors(exec, grid, domains, step, projector);
  const mpm::ImplicitSystem system{particles,
                                   grid,
                                   step,
                                   stiffness,
                                   projector,
                                   domains,
                                   Vec3Planes<float>(corner_displacement_.data(), domains.corners),
                                   Vec3Planes<float>(corner_force_.data(), domains.corners)};
  mpm::jacobi_inverse_diagonal(exec, system, inverse_diagonal);

  // x₀ = v*, r₀ = S M v* − A v*.
  mpm::load_explicit_velocities(exec, system, x);
  mpm::apply_mass(exec, system, x, r);
  const double momentum_norm = std::sqrt(dot_(exec, r, r));
  mpm::apply_implicit_operator(exec, system, x, q);
  axpy(exec, -1.0f, q, r);

  double residual_norm = std::sqrt(dot_(exec, r, r));
  const double reference = std::max(momentum_norm, residual_norm);
  const double threshold = double(config_.tolerance) * reference;
  mpm::apply_preconditioner(exec, system, inverse_diagonal, r, z);
  memory::copy(p.data(), exec.backend, z.data(), exec.backend, std::size_t(unknowns) * sizeof(float), exec.stream);
  double rz = dot_(exec, r, z);
  std::int32_t iterations = 0;
  bool broke_down = false;
  while (residual_norm > threshold && iterations < config_.max_iterations) {
    mpm::apply_implicit_operator(exec, system, p, q);
    const double pq = dot_(exec, p, q);
    // S A S is positive definite on the range of S: only rounding or a non-finite state gets here.
    if (!(pq > 0.0) || !std::isfinite(pq)) {
      broke_down = true;
      break;
    }
    const double alpha = rz / pq;
    axpy(exec, float(alpha), p, x);
    axpy(exec, float(-alpha), q, r);
    mpm::apply_preconditioner(exec, system, inverse_diagonal, r, z);
    const double rz_next = dot_(exec, r, z);
    xpby(exec, z, float(rz_next / rz), p);
    rz = rz_next;
    residual_norm = std::sqrt(dot_(exec, r, r));
    ++iterations;
  }

  ImplicitSolveReport report;
  report.iterations = iterations;
  report.relative_residual = reference > 0.0 ? residual_norm / reference : 0.0;
  report.converged = !broke_down && std::isfinite(residual_norm) && residual_norm <= threshold;
  ++totals_.solves;
  totals_.iterations += iterations;
  totals_.most_iterations = std::max(totals_.most_iterations, iterations);
  if (report.converged) {
    mpm::store_velocities(exec, system, x);
  } else {
    ++totals_.not_converged;
    spdlog::warn(
        "step {}: the implicit solve did not converge ({} CG iterations{}, relative residual {:.3g}, "
        "tolerance {:.3g}); keeping the explicit velocities for this step",
        step_number, iterations, broke_down ? ", broke down" : "", report.relative_residual, config_.tolerance);
  }
  return report;
}

}  // namespace romp::engine
