// ReducedSim: the online stage of the reduced-order MPM (ROM paper, Alg. 2): only the generalized
// coordinates x̂ and velocity v̂ evolve; each substep decodes the full-space kinematics the step needs
// from the deformation map g, runs the MPM update for a few sample material points, and projects
// their updated velocities (and positions) back onto the manifold.
//
// Quadrature (Sec. 3.2.2). Lagrangian (Alg. 3): the samples and their neighbours, the material points
// whose stencils reach the samples' grid nodes (kernels/rom/stencil_neighbours.h). Finding them takes
// g's positions at every point (a forward pass, a quarter of what the full kinematics cost per point);
// the Jacobians, P2G and the stress are then paid only at the neighbours. Where the neighbours would be
// most of the body anyway (few points per sample's reach), every point is the quadrature, which gives
// the samples the same P2G without the search. Eulerian (Alg. 4) places ℓ points per cell per axis in
// the cells whose points reach the samples' grid nodes and inverts g there: its cost depends on the
// sample count, not on P.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "host/engine/sim_config.h"
#include "host/engine/step_inputs.h"
#include "host/geometry/random.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/error.h"
#include "kernels/core/event_timeline.h"
#include "kernels/core/exec.h"
#include "kernels/core/index_select.h"
#include "kernels/math/vec3.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/rom/deformation_map_eval.h"
#include "kernels/rom/eulerian_quadrature.h"
#include "kernels/rom/position_projection.h"
#include "kernels/rom/sample_neighbourhood.h"

namespace romp::engine {

enum class RomQuadrature { Lagrangian, Eulerian };

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
};

class ReducedSim {
 public:
  // `reference`: the material points in the reference configuration (x, with F = I), with their mass,
  // volume, material and Dirichlet group, as scene_setup samples them. `xhat` is x̂ at t = 0 (the
  // encoder's value for the initial state); v̂ at t = 0 is the least-squares fit of reference.v.
  ReducedSim(const Exec& exec, FullOrderConfig config, const mpm::ParticleInit& reference,
             rom::DeformationMapWeights map, std::vector<float> xhat, ReducedOptions options);

  float stable_dt() const;
  void substep(float dt);
  // Substeps until time() reaches t (the last substep is shortened to land on t), or until `stop`, asked
  // before each substep, answers true; returns whether time() reached t.
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
  // Eulerian points inverted so far (used, outside or unconverged), summed over the substeps.
  std::int64_t eulerian_points() const {
    const rom::QuadratureTally tally = quadrature_tally();
    return tally.points[0] + tally.points[1] + tally.points[2];
  }
  // The Eulerian quadrature's mass in the last substep (kg): with every point sampled, the body's mass.
  double last_quadrature_mass() const { return quadrature_tally().last_mass; }
  // Lagrangian quadrature: whether it searches the samples' neighbours.
  bool searches_neighbours() const { return search_neighbours_; }
  // The quadrature points of the last substep: Lagrangian, the samples and their neighbours or every
  // material point; Eulerian, the points inverted (inside the body or not; P2G reads those inside).
  Index last_quadrature_count() const { return quadrature_.count; }
  // Lagrangian quadrature points summed over the substeps so far.
  std::int64_t lagrangian_quadrature_points() const { return lagrangian_points_; }
  std::vector<std::pair<std::string, double>> stage_seconds() const;

 private:
  std::vector<std::int32_t> choose_samples();
  void resize_samples(Index m);
  // The quadrature points of this substep in quadrature_, and their view.
  mpm::ParticleView lagrangian_quadrature(Index m);
  void every_point_quadrature();
  mpm::ParticleView eulerian_quadrature(Index m);
  void build_occupancy(const mpm::ParticleInit& reference);
  rom::DeformationMapView<float> map_view() const;
  // Evaluates g at the reference points `X` (n of them) for x̂ on the device.
  void evaluate_map(Vec3Planes<const float> X, const rom::DeformationMapOutputs<float>& out);
  Span<float> xhat_device() { return latent_device_.span().subspan(0, latent_); }
  Span<float> vhat_device() { return latent_device_.span().subspan(latent_, latent_); }
  // Solves the r × r system of rom::normal_equations on the host; returns (y, squared residual at y = 0).
  std::pair<std::vector<double>, double> solve_projection(Span<const float> dg_dxhat, Vec3Planes<const float> target,
                                                          Vec3Planes<const float> reference);
  // The error of a projection whose normal equations have no solution.
  Error singular_projection() const;
  // Throws NonFiniteError when x̂ or v̂ is not finite after `stage`.
  void check_latent(const char* stage) const;
  // Throws NonFiniteError naming the material point when one of the `count` positions in `x` (3 planes: the
  // samples' or the Lagrangian quadrature's, `index` their material points, or empty for every point)
  // lies outside the grid's interior: x̂ has gone where the map no longer describes the body.
  void check_inside_domain(const DeviceBuffer<float>& x, Index count, Span<const std::int32_t> index);
  rom::QuadratureTally quadrature_tally() const;
  rom::GaussNewtonState gauss_newton_state() const;  // zero without the position projection

  Exec exec_;
  FullOrderConfig config_;
  StepInputs inputs_;
  mpm::SparseGrid grid_;
  ReducedOptions options_;
  rom::DeformationMapWeights map_;
  DeviceBuffer<float> map_parameters_;
  int latent_;
  Index points_;

  // The material points in reference order (X, mass, volume, material, Dirichlet group, id).
  DeviceBuffer<float> X_, mass_, volume0_;
  DeviceBuffer<std::int32_t> material_, dirichlet_group_, id_;
  std::vector<std::int32_t> free_points_;                 // not in a Dirichlet group
  std::vector<std::vector<std::int32_t>> group_members_;  // per Dirichlet group
  // The quadrature points of a substep (Lagrangian: the samples and their neighbours, or every material
  // point, in reference order).
  struct Quadrature {
    Index count = 0, capacity = 0;
    DeviceBuffer<float> x, X, v, C, F, mass, volume0;
    DeviceBuffer<std::int32_t> material, group, id, status;
    void allocate(Backend backend, Index n);
    // count = n, reallocating (with headroom) only when n exceeds the capacity; returns whether it did
    // (the contents are then uninitialised, C aside).
    bool resize(Backend backend, Index n);
    // These points: the points `index` of `source` (all but C, which stays 0, and status).
    void gather_from(const Exec& exec, const Quadrature& source, Span<const std::int32_t> index);
    mpm::ParticleView view();
  } quadrature_;
  // Eulerian: the quadrature points inside the body, gathered for P2G (their indices in quadrature_).
  Quadrature used_quadrature_;
  // Buffers refilled every substep are grown to the largest count so far and reused (an allocation on
  // CUDA synchronises the device); this step's elements are their prefix.
  DeviceBuffer<std::int32_t> used_index_;
  DeviceBuffer<std::int32_t> inversion_iterations_;                    // per Eulerian point, this substep
  DeviceBuffer<std::int32_t> map_evaluations_, jacobian_evaluations_;  // likewise
  DeviceBuffer<rom::QuadratureTally> tally_;                           // Eulerian: the running totals
  IndexSelector select_indices_;                                       // the used points' and the neighbours' indices
  DeviceBuffer<float> guesses_, guess_jacobians_;  // Eulerian: each point's first X and ∂g/∂X there
  rom::SampleNeighbourhood neighbourhood_;         // the nodes and Eulerian points around the samples
  // The reference state (X, mass, volume, material, Dirichlet group, id) of the material points `index`.
  void gather_reference(Span<const std::int32_t> index, Quadrature& points);
  DeviceBuffer<float> dg_dxhat_;  // Lagrangian: ∂g/∂x̂ at the quadrature points
  // Lagrangian neighbour search: g's positions at every point, the base nodes near the samples, the
  // points marked as neighbours and their indices.
  bool search_neighbours_ = false;
  DeviceBuffer<float> positions_;
  DeviceBuffer<std::int32_t> marked_, quadrature_index_;
  DeviceBuffer<std::int64_t> first_outside_;  // 1 slot for rom::find_point_outside
  // The samples: reference and current state, ∂g/∂x̂ there, and g during Gauss–Newton.
  Quadrature samples_;
  DeviceBuffer<float> sample_dg_dxhat_, model_x_;
  // Position–velocity: [x̂_{n−1} | x̂_n] and the Gauss–Newton state on the device (rom::project_positions).
  DeviceBuffer<float> xhat_history_;
  DeviceBuffer<rom::GaussNewtonState> projection_state_;
  DeviceBuffer<std::int32_t> sample_index_;
  // Eulerian: the occupancy of the reference configuration and ρ₀ per material.
  DeviceBuffer<std::int32_t> occupancy_cells_;
  rom::ReferenceOccupancy occupancy_;
  DeviceBuffer<float> densities_;
  // [x̂ | v̂ | status] on the device (rom::advance_latent), equal to xhat_ and vhat_ between substeps.
  DeviceBuffer<float> latent_device_;
  DeviceBuffer<float> speed_slot_;  // mpm::max_particle_speed's result
  DeviceBuffer<double> system_;

  std::vector<float> xhat_, vhat_;
  bool has_previous_ = false;
  geometry::Random random_;
  float max_sample_speed_ = 0.0f;
  double time_ = 0.0;
  std::int64_t steps_ = 0;
  std::int64_t lagrangian_points_ = 0;
  std::vector<std::string> stages_;       // the stage table's names, in pipeline order
  mutable EventTimeline stage_timeline_;  // read when the table is asked for
};

}  // namespace romp::engine
