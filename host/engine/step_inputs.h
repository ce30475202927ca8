// StepInputs: what an MPM substep reads besides the particles and the grid (the material table, the
// colliders, Dirichlet motions and loads at the substep's time, and the failure slots and their
// report), and the clock loop, shared by FullOrderSim and ReducedSim so both see one scene the same way.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "host/engine/sim_config.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/error.h"
#include "kernels/core/exec.h"
#include "kernels/mpm/input_schedule.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/step.h"

namespace romp::engine {

// Thrown when a stage produces a non-finite value; the run stops at the end of that substep.
class NonFiniteError : public Error {
 public:
  NonFiniteError(const std::string& message, std::int64_t step, mpm::Stage stage, std::int64_t index)
      : Error(message), step_(step), stage_(stage), index_(index) {}
  std::int64_t step() const { return step_; }
  mpm::Stage stage() const { return stage_; }
  // Particle id (initial order), node for the grid update, or -1 for a point that is no particle (an
  // Eulerian quadrature point).
  std::int64_t index() const { return index_; }

 private:
  std::int64_t step_;
  mpm::Stage stage_;
  std::int64_t index_;
};

const char* stage_name(mpm::Stage stage);

// The particle (or other quantity) a stage's recorded index stands for: the index to report and how
// to name it, e.g. a sorted slot mapped to the particle's initial index, "particle 12".
using FailureDescriber = std::function<std::pair<std::int64_t, std::string>(mpm::Stage stage, std::int64_t index)>;

class StepInputs {
 public:
  // Checks the configuration (walls, materials, cfl, flip_alpha) and uploads the material table.
  StepInputs(const Exec& exec, const FullOrderConfig& config);

  // The parameters of a substep [time, time + dt]: colliders moved to `time`, the Dirichlet motions
  // and the loads active then (computed on the device, mpm::inputs_at: nothing uploaded), failure slots
  // reset to "no failure" and the largest speed to 0.
  mpm::StepParams at(double time, float dt);
  // After a substep, one download: the stages' failure slots, the largest speed the substep's moved
  // particles stored (StepParams::largest_speed, for the next CFL step), and what reserve_readback added.
  // Returns the speed.
  float read_back();
  // Throws NonFiniteError for the first stage whose slot, as read_back read it, recorded a non-finite
  // value: "<who>non-finite value at step S (t = T s), stage X: <what>". Grid-update indices are reported
  // as grid nodes; every other stage's index goes through `describe`.
  void check_stages(const std::string& who, std::int64_t step, double time, const FailureDescriber& describe) const;
  // Room that read_back reads with the failure slots, so that a substep's checks, its next CFL speed and
  // its results come back in one download: `slots` more failure slots (reset to mpm::kNoFailure by `at`,
  // as the stages' are; ReducedSim's points outside the domain) and `floats` values (ReducedSim's
  // [x̂ | v̂ | status], FullOrderSim's "a particle left the grid"). Call once, before the first substep.
  struct Readback {
    Span<std::int64_t> slots;
    Span<float> values;
  };
  Readback reserve_readback(int floats, int slots = 0);
  // Those slots and values as the last read_back read them.
  const std::vector<std::int64_t>& readback_slots() const { return readback_slots_; }
  const std::vector<float>& readback() const { return readback_; }

  bool plastic() const { return plastic_; }
  // The largest dilatational wave speed sqrt((λ + 2μ) / ρ) over the materials (m/s), for the CFL rule.
  float max_wave_speed() const { return max_wave_speed_; }

 private:
  // The material table at `time` (strength windows applied), uploaded only when it changes.
  void upload_materials(double time);

  Exec exec_;
  FullOrderConfig config_;
  bool plastic_ = false;
  float max_wave_speed_ = 0.0f;
  DeviceBuffer<material::MaterialParams<float>> materials_;
  std::vector<bool> strength_off_;  // per material, as materials_ holds it now
  // The scene's schedule, uploaded once, and the tables `at` computes from it on the device.
  DeviceBuffer<mpm::ColliderState> collider_schedule_;
  DeviceBuffer<mpm::ScheduledMotion> motion_schedule_;
  DeviceBuffer<mpm::RegionLoad> load_schedule_;
  DeviceBuffer<Vec3<float>> traction_schedule_;
  DeviceBuffer<mpm::ColliderState> colliders_;
  DeviceBuffer<mpm::RigidMotion> dirichlet_;
  DeviceBuffer<mpm::RegionLoad> loads_;
  DeviceBuffer<Vec3<float>> tractions_;
  // kStageCount failure slots, the readback's slots, one slot whose first 4 bytes hold a float speed, then
  // the readback's floats (two per slot).
  DeviceBuffer<std::int64_t> first_failure_;
  std::vector<std::int64_t> stage_failures_, readback_slots_;
  std::vector<float> readback_;

  // The speed's slot: after the failure slots and the readback's slots.
  Index speed_slot() const { return mpm::kStageCount + Index(readback_slots_.size()); }
};

// Substeps until `time` reaches t: `substep(dt)` advances `time` by dt, `stable_dt()` says how far it
// may go. The last substep is shortened to land on t, and one shorter than 1e-3 of the stable Δt is
// merged into the one before. `stop`, where given, is asked before each substep: when it answers true
// the clock stops there, short of t. Returns whether `time` reached t.
bool advance_clock(double& time, double t, const std::function<double()>& stable_dt,
                   const std::function<void(float)>& substep, const std::function<bool()>& stop = {});

// Throws if a group of `groups` (of `what`: "particle", "domain corner") is not in `config`.
void check_dirichlet_groups(const FullOrderConfig& config, const std::vector<std::int32_t>& groups,
                            const std::string& what);

// Throws if a particle names a domain `init.domains` lacks, or a corner a Dirichlet group not in `config`.
void check_particle_domains(const FullOrderConfig& config, const mpm::ParticleInit& init);

// Throws if a particle's material or Dirichlet group is not in `config`.
void check_particle_tables(const FullOrderConfig& config, const std::vector<std::int32_t>& material,
                           const std::vector<std::int32_t>& dirichlet_group);

}  // namespace romp::engine
