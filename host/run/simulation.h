// Simulation: what the frame loop of `romp run` needs of an engine, so one loop (outputs, progress,
// interrupts, checkpoints) serves the full-order and the reduced-order simulation alike.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "host/engine/reduced_sim.h"
#include "host/engine/sim_config.h"
#include "host/engine/tracer_set.h"
#include "kernels/core/exec.h"
#include "kernels/mpm/particle_set.h"
#include "nn/io/snapshot_layout.h"

namespace romp::run {

struct DomainState {
  std::vector<float> corner_x;                // 3 planes over the corners
  float stiffening = 1.0f;                    // the last substep's domain_stiffening
  std::vector<std::int32_t> particle_domain;  // in the initial order; kNoDomain where released
};

class Simulation {
 public:
  virtual ~Simulation() = default;
  // Substeps until time() reaches t, or until `stop` (asked before each substep) answers true; returns
  // whether time() reached t.
  virtual bool advance_to(double t, const std::function<bool()>& stop) = 0;
  // The state of every material point in the initial order; every field filled (a checkpoint needs them).
  virtual io::FrameData capture() = 0;
  virtual double time() const = 0;
  virtual std::int64_t steps() const = 0;
  virtual std::vector<std::pair<std::string, double>> stage_seconds() const = 0;
  // Whether a checkpoint (particles, and domain corners when there are any) is enough to continue this simulation.
  virtual bool resumable() const = 0;
  // The state of the particle domains besides the particles (empty without domains): what embedded
  // meshes follow (the corners) and what a checkpoint needs with the particles.
  virtual DomainState domain_state() { return {}; }
  // Frames at other points than the material points (RunOptions::output_points): `X` (3 planes) in the
  // reference configuration, given before the first advance. The reduced engine decodes x, v and F
  // there (the ROM paper's super-resolution); the full-order engine carries them as tracers, as `carrier`
  // says (x and v: the paper's tracer-particle baseline, Sec. 5.2.1, with TracerCarrier::Grid).
  virtual void track_points(const std::vector<float>& X, engine::TracerCarrier carrier) = 0;
  virtual io::FrameData capture_points() = 0;
  // The fields capture_points fills.
  virtual io::FieldMask point_fields() const = 0;
  // Lines for the end-of-run report about solver health (e.g. iterations that did not converge).
  virtual std::vector<std::string> diagnostics() const { return {}; }
};

// The full-order engine from `particles`, its clock set to (time, steps) (non-zero when resumed).
std::unique_ptr<Simulation> full_order_simulation(const Exec& exec, const engine::FullOrderConfig& config,
                                                  const mpm::ParticleInit& particles, double time = 0.0,
                                                  std::int64_t steps = 0);

// The reduced-order engine: its frames decode x, F and v at every material point from x̂ (C is 0,
// the ROM carries no affine velocity). Not resumable from a frame: its state is x̂, v̂ and x̂ of the
// substep before, which a particle checkpoint does not hold.
std::unique_ptr<Simulation> reduced_simulation(const Exec& exec, const engine::FullOrderConfig& config,
                                               const mpm::ParticleInit& particles, rom::DeformationMapWeights map,
                                               std::vector<float> xhat, const engine::ReducedOptions& options);

}  // namespace romp::run
