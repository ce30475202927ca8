// FullOrderSim: explicit MLS-MPM on the sparse grid, substepped under the CFL condition.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/error.h"
#include "kernels/core/exec.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/step.h"

namespace romp {

struct MaterialSpec {
  material::MaterialParams<float> params;
  float density = 1000.0f;  // kg/m^3, for the wave speed of the CFL condition
};

// A collider's pose at t = 0 and its constant rigid motion: center(t) = center + v t,
// rotation(t) = exp(t [ω]×) rotation(0).
struct ColliderSpec {
  mpm::ColliderState initial;
};

// Particles of a Dirichlet group follow v(x) = v_lin + ω × (x − pivot(t)), pivot(t) = pivot + v_lin t.
struct DirichletSpec {
  Vec3<float> pivot;
  Vec3<float> linear_velocity;
  Vec3<float> angular_velocity;
};

struct RegionLoadSpec {
  mpm::RegionLoad load;
  double start = 0.0;  // s; the load acts for start <= t < end
  double end = 0.0;
};

struct FullOrderConfig {
  float dx = 0.0f;
  std::array<std::int32_t, 3> domain_cells{0, 0, 0};  // the domain is [0, cells dx] per axis
  Vec3<float> gravity{0.0f, -9.81f, 0.0f};
  mpm::Transfer transfer = mpm::Transfer::Apic;
  float flip_alpha = 0.95f;
  std::int32_t wall_cells = 3;
  mpm::ContactType wall_contact = mpm::ContactType::Separate;
  float wall_friction = 0.0f;
  float cfl = 0.5f;        // Δt = cfl dx / (c + |v|max)
  float fixed_dt = 0.0f;   // > 0: use this Δt instead of the CFL condition
  float max_dt = 1e-3f;    // upper bound on the CFL step (a body at rest has |v| = 0)
  std::vector<MaterialSpec> materials;
  std::vector<ColliderSpec> colliders;
  std::vector<DirichletSpec> dirichlet;
  std::vector<RegionLoadSpec> loads;
};

// Thrown when a stage produces a non-finite value; the run stops at the end of that substep.
class NonFiniteError : public Error {
 public:
  NonFiniteError(const std::string& message, std::int64_t step, mpm::Stage stage, std::int64_t index)
      : Error(message), step_(step), stage_(stage), index_(index) {}
  std::int64_t step() const { return step_; }
  mpm::Stage stage() const { return stage_; }
  std::int64_t index() const { return index_; }  // particle id (initial order), or node for the grid update

 private:
  std::int64_t step_;
  mpm::Stage stage_;
  std::int64_t index_;
};

const char* stage_name(mpm::Stage stage);

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
  bool has_plasticity() const { return plastic_; }

  // Seconds spent in each stage so far, in pipeline order (only the stages this scene runs).
  std::vector<std::pair<std::string, double>> stage_seconds() const;

 private:
  mpm::StepParams step_params(float dt);
  void check_finite();

  Exec exec_;
  FullOrderConfig config_;
  mpm::ParticleSet particles_;
  mpm::SparseGrid grid_;
  bool plastic_ = false;
  float max_wave_speed_ = 0.0f;
  DeviceBuffer<material::MaterialParams<float>> materials_;
  DeviceBuffer<mpm::ColliderState> colliders_;
  DeviceBuffer<mpm::RigidMotion> dirichlet_;
  DeviceBuffer<mpm::RegionLoad> loads_;
  DeviceBuffer<std::int64_t> first_failure_;
  double time_ = 0.0;
  std::int64_t steps_ = 0;
  std::vector<std::pair<std::string, double>> stage_seconds_;
};

}  // namespace romp
