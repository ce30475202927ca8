// ReducedSim: the online stage of the reduced-order MPM (ROM paper, Alg. 2): only the generalized
// coordinates x̂ and velocity v̂ evolve; each substep decodes the full-space kinematics the step needs
// from the deformation map g, runs the MPM update for a few sample material points, and projects
// their updated velocities (and positions) back onto the manifold.
//
// The parts own their buffers and can be tested alone: the map (deformation_map.h), the samples
// (sample_set.h), the quadrature, Lagrangian or Eulerian behind one interface (reduced_quadrature.h),
// and the projections of the reduced state (latent_projection.h); the substep runs them in the order
// of Alg. 2, with the full-order P2G, grid update and G2P between.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "host/engine/deformation_map.h"
#include "host/engine/kept_graphs.h"
#include "host/engine/latent_projection.h"
#include "host/engine/quadrature_points.h"
#include "host/engine/reduced_quadrature.h"
#include "host/engine/sample_set.h"
#include "host/engine/sim_config.h"
#include "host/engine/step_inputs.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/error.h"
#include "kernels/core/event_timeline.h"
#include "kernels/core/exec.h"
#include "kernels/core/stream_graph.h"
#include "kernels/math/vec3.h"
#include "kernels/mpm/failed_points.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/rom/deformation_map_eval.h"
#include "kernels/rom/eulerian_quadrature.h"
#include "kernels/rom/position_projection.h"

namespace romp::engine {

// Lagrangian: material points (ROM paper, Alg. 3); Eulerian: points inverted in the samples' cells (Alg. 4);
// Domains: every material point through its particle domain's corners placed by g, the transfer of the
// full-order step on particle domains that made such a model's data (reduced_quadrature.h, DomainQuadrature).
enum class RomQuadrature { Lagrangian, Eulerian, Domains };

// Whether the quadrature keeps only the samples' neighbours, the points whose stencils reach a sample's
// grid nodes (the samples' P2G is the same either way). Lagrangian: the neighbours are searched among
// the material points, or every material point is taken; Auto searches when the neighbours are bound to
// be under half the points: samples × 5³ cells × points per cell < P / 2. Eulerian: of the ℓ³ points of
// each cell near a sample, only the neighbours are inverted unless Never.
enum class NeighbourSearch { Auto, Always, Never };

enum class RomProjection {
  Velocity,          // Alg. 7: v̂ from the trial velocities, x̂ += Δt v̂
  PositionVelocity,  // Alg. 6: v̂ as Alg. 7, x̂ by Gauss–Newton on the trial positions
};

struct ReducedOptions {
  RomQuadrature quadrature = RomQuadrature::Lagrangian;
  RomProjection projection = RomProjection::Velocity;
  NeighbourSearch neighbour_search = NeighbourSearch::Auto;
  int points_per_cell = 2;  // ℓ of the Eulerian quadrature, per axis
  // Inversion of g for Eulerian points (quasi-Newton): at most this many iterations, converged within
  // inversion_tolerance × dx.
  int inversion_iterations = 20;
  float inversion_tolerance = 1e-4f;
  // Start a point's inversion from its place's last solution (kernels/rom/eulerian_warm_start.h).
  bool warm_start_inversion = true;
  // > 0: the substeps' CFL number instead of the scene's time.cfl, in (0, 1] (a hyper-reduced run may
  // need a smaller step than the full-order runs its map was trained on).
  double cfl = 0.0;
  // Sample material points drawn anew each substep (hyper-reduction); 0 or ≥ the point count: all.
  Index samples = 0;
  // Drawn from every Dirichlet group in addition, so prescribed motions reach the projection (the
  // paper: "at least 5 material points from each kinematic boundary").
  int boundary_samples = 5;
  std::uint64_t seed = 0;
  // Gauss–Newton of the position projection: at most this many iterations, stopping when a step
  // changes x̂ by less than tolerance × (1 + |x̂|).
  int gauss_newton_iterations = 10;
  double gauss_newton_tolerance = 1e-6;
  // Run each frame's substeps as one CUDA graph (GraphReplay: on CUDA by default) where the step allows: a
  // build with no round trip (at most mpm::SparseGrid::kFewPoints samples, an Eulerian candidate count that
  // stays on the device, Gauss–Newton in one block) and inputs that do not
  // change within the frame. Captured again when the frame's Δt, substep count or inputs change (the graphs
  // of the last four are kept).
  GraphReplay frame_graphs = GraphReplay::Auto;
};

class ReducedSim {
 public:
  // `reference`: the material points in the reference configuration (x, with F = I), with their mass,
  // volume, material and Dirichlet group, as scene_setup samples them. `xhat` is x̂ at t = 0 (the
  // encoder's value for the initial state); v̂ at t = 0 is the least-squares fit of reference.v.
  ReducedSim(const Exec& exec, FullOrderConfig config, const mpm::ParticleInit& reference,
             rom::DeformationMapWeights map, std::vector<float> xhat, ReducedOptions options);
  // The quadrature refers to the reference body and the simulation to its quadrature: not copied or moved.
  ReducedSim(const ReducedSim&) = delete;
  ReducedSim& operator=(const ReducedSim&) = delete;

  // The CFL step from the wave speed and the samples' largest speed in the last read-back's substeps (with the
  // domain quadrature, the wave speed of its domains' largest stiffening in them, as the full-order step).
  float stable_dt() const;
  // `count` substeps of dt, at most kMostSubstepsPerReadback, with one read-back after the last (a blocking
  // round trip on CUDA): until then nothing waits on the device, and the substeps could be replayed as a
  // CUDA graph. xhat(), vhat(), time(), steps() and stable_dt() change at the read-back. A failure still
  // stops at the substep, stage and point that failed, with the message a read-back after each substep would
  // give, and the state left as after the substep before it.
  static constexpr int kMostSubstepsPerReadback = 128;
  void substeps(float dt, int count);
  void substep(float dt) { substeps(dt, 1); }
  // Substeps of equal length, none over the stable step, until time() reaches t, read back once for each
  // kMostSubstepsPerReadback of them (an output frame's worth, or a frame's whole when shorter): the step
  // follows the speeds of the last read-back's substeps. Stops early when `stop`, asked before each
  // read-back's substeps, answers true; returns whether time() reached t.
  bool advance_to(double t, const std::function<bool()>& stop = {});

  // The state at reference points X (3 planes of n): x = g(X; x̂), F = ∇_X g, v = (∂g/∂x̂) v̂. Any
  // points of the reference body will do, e.g. a finer sampling of it (super-resolution, ROM paper,
  // Sec. 5.2.1).
  struct DecodedState {
    std::vector<float> x, F, v;  // 3, 9 and 3 planes of n
  };
  DecodedState decode(const std::vector<float>& X);
  // x = g(X; x̂) for every material point, 3 planes in the reference order.
  std::vector<float> decode_positions();

  const std::vector<float>& xhat() const { return xhat_; }
  const std::vector<float>& vhat() const { return vhat_; }
  double time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  // The largest CFL number Δt (c + |v|) / ℓ the substeps so far ran at, c the wave speed (with the quadrature's
  // stiffening), |v| the samples' largest speed when the substep started and ℓ the quadrature's CFL length (the
  // cell, or a domain's edge): the scene's cfl or less, unless the samples sped up within a read-back's substeps
  // (their step follows the speeds of the read-back before).
  double largest_cfl_number() const { return largest_cfl_; }
  // Substeps whose Gauss–Newton projection stopped at its iteration limit before converging (the device's
  // count: a download).
  std::int64_t unconverged_projections() const;
  // Gauss–Newton linearisations so far (g and ∂g/∂x̂ at the samples, each), likewise.
  std::int64_t gauss_newton_linearisations() const;
  // Eulerian quadrature points so far: used, dropped outside the body, dropped unconverged (or inverted).
  // These read the device's running totals (a download each).
  std::int64_t quadrature_points_used() const { return quadrature_tally().points[rom::kQuadratureUsed]; }
  std::int64_t quadrature_points_outside() const { return quadrature_tally().points[rom::kQuadratureOutside]; }
  std::int64_t quadrature_points_unconverged() const { return quadrature_tally().points[rom::kQuadratureUnconverged]; }
  // Iterations of g's inversion so far, summed over the Eulerian points.
  std::int64_t inversion_iterations() const { return quadrature_tally().iterations; }
  // Evaluations of g at the Eulerian points so far, and those of them that also gave both Jacobians.
  std::int64_t eulerian_map_evaluations() const { return quadrature_tally().evaluations; }
  std::int64_t eulerian_jacobian_evaluations() const { return quadrature_tally().jacobian_evaluations; }
  // Eulerian points whose inversion started from their place's last solution, so far.
  std::int64_t eulerian_warm_starts() const { return quadrature_tally().warm_starts; }
  // Eulerian points inverted so far (used, outside or unconverged), summed over the substeps.
  std::int64_t eulerian_points() const {
    const rom::QuadratureTally tally = quadrature_tally();
    return tally.points[0] + tally.points[1] + tally.points[2];
  }
  // The Eulerian quadrature's mass in the last substep (kg): with every point sampled, the body's mass.
  double last_quadrature_mass() const { return quadrature_tally().last_mass; }
  // Lagrangian quadrature: whether it searches the samples' neighbours.
  bool searches_neighbours() const { return lagrangian_ && lagrangian_->searches_neighbours(); }
  // The quadrature points of the last substep: Lagrangian, the samples and their neighbours or every
  // material point; Eulerian, the points inverted (inside the body or not; P2G reads those inside).
  Index last_quadrature_count() const { return quadrature_->last_count(exec_); }
  // Domain quadrature: the corners g places each substep (0 for the other quadratures).
  Index domain_corners() const { return domains_ ? domains_->corner_count() : 0; }
  // Lagrangian (or domain) quadrature points summed over the substeps so far (with the neighbour search, a
  // download).
  std::int64_t lagrangian_quadrature_points() const {
    return lagrangian_ ? lagrangian_->points_so_far(exec_) : domains_ ? domains_->points_so_far() : 0;
  }
  std::vector<std::pair<std::string, double>> stage_seconds() const;
  // Each stage's launches so far (memory::Traffic::launches): on CUDA, outside a graph, a few microseconds
  // of the host's time each. Frames run as graphs count in the last stage, "frame_graphs" (where they can), one launch
  // each.
  std::vector<std::pair<std::string, std::int64_t>> stage_launches() const;
  // Whether frames run as graphs (ReducedOptions::frame_graphs and the step allows it), how many graphs were
  // captured, and how many frames ran as one.
  bool runs_frame_graphs() const { return graphs_possible_; }
  std::int64_t graph_captures() const { return frame_graphs_.captures(); }
  std::int64_t graph_frames() const { return graph_frames_; }

 private:
  // The elastic wave speed the CFL step takes: at rest, scaled by the domains' stiffening.
  float wave_speed() const;
  // Throws NonFiniteError when x̂ or v̂ is not finite after `stage`.
  void check_latent(const char* stage) const;
  // A read-back row's own slots: the first point outside the domain, of the samples and of the quadrature's
  // material points, then the records (mpm::FailedPoint) of the points that the row's slots name: P2G's
  // (quadrature points), G2P's (samples) and the two outside.
  enum ReadbackSlot { kSampleOutside = 0, kQuadratureOutside = 1, kFirstRecord = 2 };
  enum FailedPointRecord { kP2GPoint = 0, kG2PPoint = 1, kSampleOutsidePoint = 2, kQuadratureOutsidePoint = 3 };
  static constexpr int kReadbackSlots = kFirstRecord + 4 * mpm::kFailedPointWords;

  // The stages of one substep with parameters `step`, with nothing read back: its row of the read-back gets its
  // failure slots, the records of the points they name, and [x̂ | v̂ | status] after it. `staged_substep` < 0:
  // the next samples drawn, each stage timed; otherwise substep k of a frame captured as a graph (its staged
  // samples, untimed).
  void run_substep(const mpm::StepParams& step, Index staged_substep);
  // The frame's substeps as one graph (captured when its key changed), where allowed: returns whether it ran.
  bool run_frame_graph(float dt, int count);
  // Moves the points at x back inside the grid's interior, noting the first that was outside in the row's
  // slot `slot` (rom::keep_points_inside): the substep goes on without waiting, on positions the grid holds.
  // With `live`, a count on the device, only the first live[0] points.
  void keep_inside_domain(Vec3Planes<float> x, Span<std::int64_t> row_slots, ReadbackSlot slot,
                          Span<const std::int64_t> live = {});
  // After a read-back, the substeps' rows in order: each checked as if read back alone, its result kept.
  void accept_substeps(float dt, int count);
  // The point a read-back row's record holds.
  mpm::FailedPoint failed_point(int row, FailedPointRecord record) const;
  // Throws NonFiniteError naming the first material point that was outside the domain in read-back row
  // `row` (x̂ has gone where the map no longer describes the body), samples first, with its position decoded
  // afresh at the substep's x̂ (the step moved it inside).
  void throw_if_outside_domain(int row);
  // The error of a projection whose normal equations have no solution.
  Error singular_projection() const;
  rom::QuadratureTally quadrature_tally() const;

  OwnedStream stream_;  // where the caller's is CUDA's legacy default stream, which cannot be captured
  Exec exec_;
  FullOrderConfig config_;
  StepInputs inputs_;
  mpm::SparseGrid grid_;
  ReducedOptions options_;
  DeformationMap map_;
  ReferenceBody reference_;
  SampleSet samples_;
  // The quadrature: one of the three, and `quadrature_` pointing to it.
  std::optional<LagrangianQuadrature> lagrangian_;
  std::optional<EulerianQuadrature> eulerian_;
  std::optional<DomainQuadrature> domains_;
  ReducedQuadrature* quadrature_ = nullptr;
  LatentProjection latent_;

  std::vector<float> xhat_, vhat_;  // [x̂ | v̂] after the last substep read back
  float max_sample_speed_ = 0.0f;   // the samples' largest in the substeps of the last read-back
  float last_sample_speed_ = 0.0f;  // theirs after the last substep read back
  float stiffening_ = 1.0f;         // the quadrature's largest in the substeps of the last read-back (1 without)
  double largest_cfl_ = 0.0;
  double time_ = 0.0;
  std::int64_t steps_ = 0;
  std::vector<std::string> stages_;       // the stage table's names, in pipeline order
  mutable EventTimeline stage_timeline_;  // read when the table is asked for
  std::vector<std::int64_t> stage_launches_;

  // The frames' graphs and what each was captured for: the frame's inputs and where its samples are staged.
  // A few are kept: advance_to's substep count may alternate between two values from frame to frame.
  struct FrameKey {
    StepInputs::FrameShape inputs;
    const void* samples = nullptr;
    bool operator==(const FrameKey& other) const { return inputs == other.inputs && samples == other.samples; }
  };
  static constexpr std::size_t kKeptFrameGraphs = 4;
  bool graphs_possible_ = false;
  KeptGraphs<FrameKey> frame_graphs_{kKeptFrameGraphs};
  std::int64_t graph_frames_ = 0;
};

}  // namespace romp::engine
