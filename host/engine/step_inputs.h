// StepInputs: what an MPM substep reads besides the particles and the grid (the material table, the
// colliders, Dirichlet motions and loads at the substep's time, and the failure slots and their
// report), and the clock loop, shared by FullOrderSim and ReducedSim so both see one scene the same way.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
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
  // and the loads active then (computed on the device, mpm::inputs_at: nothing uploaded), and the next
  // read-back row, reset: failure slots "no failure", the largest speed 0.
  mpm::StepParams at(double time, float dt);

  // A frame of `count` substeps of dt from `time` as one CUDA graph: what stays fixed over its substeps, which
  // the graph bakes in (the active colliders, loads and tractions, the material table), or nothing where the
  // frame's substeps differ in them (it then runs substep by substep). Puts the frame's material table on the
  // device (an upload where it changed), so the frame itself uploads nothing. `at_in_frame(k)` then gives
  // substep k's parameters with its time read on the device from the frame's start, which `start_frame`
  // writes there (one upload), and `claim_rows` takes the rows of a frame whose graph was replayed.
  struct FrameShape {
    float dt = 0.0f;
    int count = 0;
    mpm::ActiveInputs active;
    const void* materials = nullptr;
    bool operator==(const FrameShape& other) const;
  };
  std::optional<FrameShape> frame_shape(double time, float dt, int count);
  void start_frame(double time);
  mpm::StepParams at_in_frame(const FrameShape& frame, int substep);
  void claim_rows(int count);
  // Forgets the rows handed out since the last read-back (a failed capture ran none of their substeps).
  void discard_pending_rows() { pending_rows_ = 0; }

  // The read-back: a row per substep since the last read_back, each holding the stages' failure slots, the
  // largest speed the substep's moved particles stored (StepParams::largest_speed, for the next CFL step)
  // and room its owner reserved, so that many substeps' checks, speeds and results come back in one
  // download. `slots` more failure slots a row (reset to mpm::kNoFailure by `at`, as the stages' are:
  // ReducedSim's points outside the domain and its failed points' records) and `floats` values (ReducedSim's
  // [x̂ | v̂ | status], FullOrderSim's "a particle left the grid"); `rows`: the most substeps between two
  // read-backs. Call at most once, before the first substep (otherwise: no reserved room, one row).
  void reserve_readback(int floats, int slots, int rows = 1);
  // The reserved room of the row the last `at` handed out, on the device.
  struct Row {
    Span<std::int64_t> slots;
    Span<float> values;
  };
  Row readback_row();
  // One download: the rows of the substeps since the last read_back. Returns how many.
  int read_back();
  // Row `row` (0: the first substep since the read-back before) as read_back read it.
  float largest_speed(int row) const;
  Span<const std::int64_t> readback_slots(int row) const;
  Span<const float> readback_values(int row) const;
  // Throws NonFiniteError for the first stage whose slot in row `row` recorded a non-finite value:
  // "<who>non-finite value at step S (t = T s), stage X: <what>". Grid-update indices are reported as grid
  // nodes; every other stage's index goes through `describe`.
  void check_stages(int row, const std::string& who, std::int64_t step, double time,
                    const FailureDescriber& describe) const;
  // Whether a stage's failure slot in row `row` recorded a non-finite value.
  bool failed(int row) const;

  bool plastic() const { return plastic_; }
  // The largest dilatational wave speed sqrt((λ + 2μ) / ρ) over the materials (m/s), for the CFL rule.
  float max_wave_speed() const { return max_wave_speed_; }

 private:
  // The material table at `time` (strength windows applied), uploaded only when it changes.
  void upload_materials(double time);
  std::vector<bool> strength_off_at(double time) const;
  mpm::ActiveInputs active_at(double time) const;
  // The parameters of a substep from `time` with `active` inputs, and its read-back row.
  mpm::StepParams params(const mpm::SubstepTime& time, float dt, const mpm::ActiveInputs& active);

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
  DeviceBuffer<double> frame_start_;  // at_in_frame's clock
  // The read-back rows, each row_words() long: kStageCount failure slots, the reserved slots, one word whose
  // first 4 bytes hold a float speed, then the reserved floats (two per word).
  DeviceBuffer<std::int64_t> rows_;
  int slots_ = 0, floats_ = 0, most_rows_ = 1;
  bool reserved_ = false;
  int pending_rows_ = 0;            // handed out by `at` since the last read_back
  std::vector<std::int64_t> read_;  // the rows the last read_back read

  Index speed_word() const { return mpm::kStageCount + slots_; }
  Index row_words() const { return speed_word() + 1 + (floats_ + 1) / 2; }
  // Row `row` of read_, checked to have been read.
  const std::int64_t* read_row(int row) const;
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
