// FullOrderSim: MLS-MPM on the sparse grid, substepped under the CFL condition; explicit, or with
// the implicit velocity solve between grid update and G2P.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/implicit_grid_solver.h"
#include "host/sim_config.h"
#include "host/step_inputs.h"
#include "kernels/core/error.h"
#include "kernels/core/exec.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/step.h"

namespace romp {


class FullOrderSim {
 public:
  FullOrderSim(const Exec& exec, FullOrderConfig config, const mpm::ParticleInit& init);

  // The Δt the CFL condition allows now (or the fixed Δt).
  float stable_dt();
  // One substep of length dt.
  void substep(float dt);
  // Substeps until time() reaches t (the last substep is shortened to land on t).
  void advance_to(double t);
  // Sets the clock of a run resumed from a checkpoint whose particle state was passed to the constructor.
  void restore_clock(double time, std::int64_t steps);

  double time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  const Exec& exec() const { return exec_; }
  const FullOrderConfig& config() const { return config_; }
  mpm::ParticleSet& particles() { return particles_; }
  const mpm::SparseGrid& grid() const { return grid_; }
  bool has_plasticity() const { return inputs_.plastic(); }
  // The implicit solver's counts; nullptr for the explicit integrator.
  const ImplicitSolveTotals* implicit_totals() const { return implicit_ ? &implicit_->totals() : nullptr; }

  // Seconds spent in each stage so far, in pipeline order (only the stages this scene runs).
  std::vector<std::pair<std::string, double>> stage_seconds() const;

 private:

  Exec exec_;
  FullOrderConfig config_;
  mpm::ParticleSet particles_;
  mpm::SparseGrid grid_;
  StepInputs inputs_;
  std::optional<ImplicitGridSolver> implicit_;  // with Integrator::Implicit only
  double time_ = 0.0;
  std::int64_t steps_ = 0;
  std::vector<std::pair<std::string, double>> stage_seconds_;
};

}  // namespace romp
