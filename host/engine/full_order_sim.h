// FullOrderSim: MLS-MPM on the sparse grid, substepped under the CFL condition; explicit, or with
// the implicit velocity solve between grid update and G2P.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/engine/implicit_grid_solver.h"
#include "host/engine/kept_graphs.h"
#include "host/engine/sim_config.h"
#include "host/engine/stage_clock.h"
#include "host/engine/step_inputs.h"
#include "host/engine/tracer_set.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/error.h"
#include "kernels/core/event_timeline.h"
#include "kernels/core/exec.h"
#include "kernels/core/stream_graph.h"
#include "kernels/mpm/particle_domains.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/step.h"

namespace romp::engine {

class NeuralMaterials;  // host/neural_materials.h: LibTorch stays out of this header

// How much dynamic enrichment a run used: the share of domain particles that enriched their corners,
// summed over substeps, and its largest value.
struct EnrichmentStatistics {
  std::int64_t substeps = 0;
  double share_sum = 0.0;
  double largest_share = 0.0;
  std::int64_t largest_share_step = 0;
};

// How often the particles were sorted by block (each sort also rebuilds a grid that follows the sort), and
// how many of those sorts came early because a particle's stencil had left the grid built at the last one.
struct SortStatistics {
  std::int64_t sorts = 0;
  std::int64_t early_sorts = 0;
};

class FullOrderSim {
 public:
  // `init.domains`, when not empty, gives the particles it names hexahedral domains (particle_domains.h).
  FullOrderSim(const Exec& exec, FullOrderConfig config, const mpm::ParticleInit& init);
  FullOrderSim(FullOrderSim&&);
  FullOrderSim& operator=(FullOrderSim&&);
  ~FullOrderSim();

  // The Δt the CFL condition allows now (or the fixed Δt).
  float stable_dt();
  // One substep of length dt, read back after it (one download).
  void substep(float dt);
  // Substeps until time() reaches t, or until `stop` answers true; returns whether time() reached t.
  // Substep by substep (each with the CFL step of the speed the one before left, the last shortened to land on
  // t, `stop` asked before each), or, where runs_batches(), in batches: substeps of one length planned for the
  // speed now (with a quarter more and what gravity adds over a batch), at most kMostSubstepsPerBatch a batch,
  // read back once after it (one download), and, from the second batch on where the batch's inputs do not
  // change within it, replayed as one CUDA graph (FullOrderConfig::frame_graphs); `stop` is asked before each
  // batch. A batch in which a substep's speed outran the step it was planned with (a collider struck, say) or a
  // stage failed goes back to where it started (ParticleSet::restore), and the rest of the span runs substep
  // by substep, which also reports a failure at its substep, stage and particle.
  bool advance_to(double t, const std::function<bool()>& stop = {});
  static constexpr int kMostSubstepsPerBatch = 128;
  // Sets the clock of a run resumed from a checkpoint whose particle state was passed to the constructor.
  void restore_clock(double time, std::int64_t steps);

  double time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  const Exec& exec() const { return exec_; }
  const FullOrderConfig& config() const { return config_; }
  const mpm::ParticleSet& particles() const { return particles_; }
  // The particles, to change (or read): the next stable_dt then measures their speed anew.
  mpm::ParticleSet& particles() {
    last_particle_speed_.reset();
    sorted_ = false;  // they may move: the next substep sorts them and builds its grid anew
    return particles_;
  }
  const mpm::SparseGrid& grid() const { return grid_; }
  // The particle domains of the scene's objects that asked for them (objects.domains), if any.
  const std::optional<mpm::ParticleDomains>& domains() const { return domains_; }
  // The share of domain particles whose corners were enriched in the last substep (0 without enrichment).
  double enriched_share() const { return last_enriched_share_; }
  const EnrichmentStatistics& enrichment_statistics() const { return enrichment_; }
  const SortStatistics& sort_statistics() const { return sorting_; }
  // Whether the grid is built when the particles are sorted and kept until the next sort (sort_every > 1,
  // without particle domains or tracers), rather than built from the particles' positions every substep.
  bool grid_follows_sort() const { return sort_every_ > 1 && !domains_ && !tracers_; }
  // Whether plastic materials' return map runs in G2P (FullOrderConfig::return_map; not with particle domains).
  bool return_map_in_g2p() const {
    return inputs_.plastic() && !domains_ && config_.return_map == ReturnMapPass::InG2P;
  }
  // Whether a substep leaves the sort's count of particle blocks and the grid's count of active blocks on the
  // device (no round trip: the substep's one download is its read-back row): with at most
  // SparseGrid::kFewPoints particles, no particle domains and the explicit integrator, where launches over a
  // bound (the particle count, 8 blocks a particle) cost less than the round trip that would size them. The
  // grid built with a sort and kept (grid_follows_sort) still reads its count back when it is built.
  bool counts_on_device() const { return particles_.count() <= mpm::SparseGrid::kFewPoints && !domains_ && !implicit_; }
  // Whether advance_to runs batches of substeps: where the counts stay on the device and the grid is built from
  // the particles every substep, without a learned law (its LibTorch ops) or tracers.
  bool runs_batches() const { return counts_on_device() && !grid_follows_sort() && !neural_ && !tracers_; }
  // Whether batches are replayed as graphs (FullOrderConfig::frame_graphs, and no capture has failed).
  bool replays_batch_graphs() const {
    return runs_batches() && replays_graphs(config_.frame_graphs, exec_) && !graphs_failed_;
  }
  // Batches replayed as one graph, graphs captured, and batches that went back to their start.
  std::int64_t graph_batches() const { return graph_batches_; }
  std::int64_t graph_captures() const { return batch_graphs_.captures(); }
  std::int64_t rolled_back_batches() const { return rolled_back_batches_; }
  // The implicit solver's counts; nullptr for the explicit integrator.
  const ImplicitSolveTotals* implicit_totals() const { return implicit_ ? &implicit_->totals() : nullptr; }

  // Tracers (host/tracer_set.h): passive points starting at `X` (3 planes), carried from now on by the
  // domains that hold them or else by the grid's velocity (TracerCarrier::Material), or by the grid's velocity
  // alone (Grid); they do not act on the simulation. Their positions and velocities in the order of `X`.
  // Tracers end the batches of substeps (runs_batches): set them before the first batch replayed as a graph.
  void set_tracers(const std::vector<float>& X, TracerCarrier carrier = TracerCarrier::Material);
  std::vector<float> tracer_positions_on_host() const;
  std::vector<float> tracer_velocities_on_host() const;

  // Seconds spent in each stage so far, in pipeline order (only the stages this scene runs; batches replayed
  // as graphs in the last, "batch_graphs", where they are).
  std::vector<std::pair<std::string, double>> stage_seconds() const;
  // Each stage's launches so far (memory::Traffic::launches): on CUDA, outside a graph, a few microseconds
  // of the host's time each; a replayed batch counts one.
  std::vector<std::pair<std::string, std::int64_t>> stage_launches() const;

 private:
  // Frees the particles (and corners) of every group whose `end` has come by `time`: at the first substep that
  // starts at or after it (also the first substep of a run resumed later).
  void release_ended_dirichlet_groups(double time);
  bool enriching() const { return domains_ && config_.enrichment_threshold > 0.0f; }
  // The particles' largest speed now: the last substep's, or reduced afresh (a download).
  float particle_speed();
  // The CFL step for particles as fast as `speed`.
  float cfl_step(float speed);
  // The step a batch is planned with (advance_to).
  float batch_step();
  // The launches of one substep with parameters `step` as the simulation's step `step_number` (which decides
  // whether it sorts), stage by stage through `timed`; nothing read back. Returns whether it sorted.
  bool run_substep(const mpm::StepParams& step, std::int64_t step_number, StageClock& timed);
  // `count` substeps of dt from time(), as a graph where allowed, read back once; false when a substep broke
  // the CFL step or failed and the batch went back to its start.
  bool run_batch(float dt, int count);
  // The batch's substeps as one graph (captured when its inputs changed): false where not allowed.
  bool replay_batch(float dt, int count);
  // Checks a batch's rows and keeps its result; false, with the state of its start, when a substep broke the
  // CFL step or failed. `speed`: the particles' largest speed at its start.
  bool accept_batch(float dt, int count, float speed, const std::vector<bool>& released);

  // Where the caller's stream is CUDA's legacy default one, which cannot be captured (held by pointer: exec_
  // keeps its handle when the simulation moves).
  std::unique_ptr<OwnedStream> stream_;
  Exec exec_;
  FullOrderConfig config_;
  mpm::ParticleSet particles_;
  std::optional<mpm::ParticleDomains> domains_;
  mpm::SparseGrid grid_;
  StepInputs inputs_;
  DeviceBuffer<float> speed_slot_;  // mpm::max_particle_speed's result
  // The particles' largest speed at the end of the last substep, read back with its failure slots, for
  // the next CFL step; empty before the first substep and after particles() was handed out (until reduced
  // afresh).
  std::optional<float> last_particle_speed_;
  // Substeps between block sorts (config.sort_every resolved for the backend; the sort falls on steps that
  // are multiples of it, and on a simulation's first substep), and whether a sort has run.
  int sort_every_ = 1;
  bool sorted_ = false;
  SortStatistics sorting_;
  std::optional<ImplicitGridSolver> implicit_;  // with Integrator::Implicit only
  std::unique_ptr<NeuralMaterials> neural_;     // when some material is a learned law
  std::optional<TracerSet> tracers_;
  double time_ = 0.0;
  std::int64_t steps_ = 0;
  std::vector<std::string> stages_;       // the stage table's names, in pipeline order
  mutable EventTimeline stage_timeline_;  // read when the table is asked for
  std::vector<std::int64_t> stage_launches_;
  std::vector<bool> released_;  // per Dirichlet group
  double last_enriched_share_ = 0.0;
  EnrichmentStatistics enrichment_;
  // Batches (advance_to): the state each starts from, their graphs by inputs, and their counts.
  mpm::ParticleSet::Snapshot batch_start_;
  // A frame's batches take at most two shapes (full ones and the rest), and the step may alternate between two.
  static constexpr std::size_t kKeptBatchGraphs = 4;
  KeptGraphs<StepInputs::FrameShape> batch_graphs_{kKeptBatchGraphs};
  bool buffers_sized_ = false;  // a substep ran in this process: a capture allocates nothing
  bool graphs_failed_ = false;
  std::int64_t graph_batches_ = 0, rolled_back_batches_ = 0;
};

}  // namespace romp::engine
