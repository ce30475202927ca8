// Stability cases for the robust-elasticity suite: a small elastic cube put through one extreme
// scenario with one material, one integrator and plain or enriched particles, run under a budget,
// and judged by whether it ends finite with bounded energy or stops early with a clear error.
#pragma once

#include <cstdint>
#include <string>

#include "kernels/core/exec.h"
#include "kernels/material/material.h"

namespace romp::analysis {

enum class StabilityScenario {
  FreeFallBounce,   // dropped on the floor, 0.4 s
  CompressRelease,  // pressed to 5 % of its height by a plate that lets go at 0.1 s, then 0.2 s free
  ForcedInversion,  // its top layer driven through its bottom layer in 0.1 s, then released for 0.2 s
  Spin,             // spinning at 10 rad/s in open space, 0.3 s
  WallImpact,       // thrown at a wall at 50 m/s, 0.01 s
};

struct StabilityCase {
  material::MaterialModel model = material::MaterialModel::FixedCorotated;
  double youngs_modulus = 1e6;  // Pa
  double poissons_ratio = 0.3;
  StabilityScenario scenario = StabilityScenario::FreeFallBounce;
  bool enriched = false;  // particle domains with enrichment at 0.6, else plain particles
  // Implicit: the Newton step at cfl kImplicitStabilityCfl (with domains, enriched corners are
  // unknowns of the solve beside the grid nodes).
  bool implicit = false;

  // "fixed-corotated/E1e+06/nu0.30/free-fall-bounce/plain/explicit", the case's name in reports.
  std::string name() const;
};

// A case stops, without failing, when it has used either budget.
struct StabilityBudget {
  std::int64_t max_substeps = 20000;
  double max_wall_seconds = 60.0;
};

struct StabilityOutcome {
  enum class Status { Finished, NonFinite, Error, SubstepBudget, TimeBudget };
  Status status = Status::Finished;
  double simulated_seconds = 0.0, end_seconds = 0.0;
  std::int64_t substeps = 0;
  double wall_seconds = 0.0;
  // The largest total energy (kinetic, elastic, gravitational) after the case's reference instant
  // over the energy at that instant: t = 0, or the release for the cases driven by a press or grips.
  double energy_ratio = 0.0;
  // The largest share of domain particles that enriched their corners in one substep (0 when plain).
  double largest_enriched_share = 0.0;
  std::string message;  // the error of a run that stopped

  // Ended finite with energy_ratio <= kStabilityEnergyBound, or stopped early with a message (a
  // NonFiniteError names step, stage and particle); a spent budget is neither a pass nor a failure.
  bool acceptable() const;
  const char* status_name() const;
};

// The implicit cases' step: 8 times the explicit limit's cfl of 0.5.
inline constexpr float kImplicitStabilityCfl = 4.0f;

// Energy may grow this much past the reference: bounded, not conserved (explicit MPM and PIC/FLIP
// neither conserve nor, at these speeds, keep energy monotone).
inline constexpr double kStabilityEnergyBound = 2.0;

StabilityOutcome run_stability_case(const Exec& exec, const StabilityCase& c, const StabilityBudget& budget);

}  // namespace romp::analysis
