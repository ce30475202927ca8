// The quadrature of a reduced substep (ROM paper, Sec. 3.2.2): the points whose P2G gives the samples'
// grid nodes their mass and force, behind one interface, Lagrangian (Alg. 3) or Eulerian (Alg. 4).
//
// Lagrangian: the samples and their neighbours, the material points whose stencils reach the samples'
// grid nodes (kernels/rom/stencil_neighbours.h). Finding them takes g's positions at every point (a
// forward pass, a quarter of what the full kinematics cost per point); the Jacobians, P2G and the
// stress are then paid only at the neighbours. Where the neighbours would be most of the body anyway
// (few points per sample's reach), every point is the quadrature, which gives the samples the same P2G
// without the search. Eulerian: ℓ points per cell per axis in the cells whose points reach the samples'
// grid nodes, with g inverted there: its cost depends on the sample count, not on the point count.
// Domains: every material point through its particle domain's corners, decoded from g, as the full-order
// step on particle domains transfers (kernels/rom/domain_quadrature.h), for maps trained on such data.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "host/engine/deformation_map.h"
#include "host/engine/quadrature_points.h"
#include "host/engine/sample_set.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/core/index_select.h"
#include "kernels/mpm/failed_points.h"
#include "kernels/mpm/particle_domains.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/step.h"
#include "kernels/rom/eulerian_quadrature.h"
#include "kernels/rom/eulerian_warm_start.h"
#include "kernels/rom/sample_neighbourhood.h"

namespace romp::engine {

class ReducedQuadrature {
 public:
  virtual ~ReducedQuadrature() = default;

  // The quadrature points at x̂_n, v̂_n around this substep's samples (decoded), for P2G: the view's count of
  // them, or where live_count() is given, the first live_count()[0] (the view's count is then a bound).
  virtual mpm::ParticleView build(const Exec& exec, const DeformationMap& map, const SampleSet& samples,
                                  Span<const float> xhat, Span<const float> vhat) = 0;
  // How many of the last build's points P2G reads, a value on the device, where the build did not count
  // them on the host; empty otherwise.
  virtual Span<const std::int64_t> live_count() const { return {}; }

  // P2G from the last build's points (`points`, its view) into the samples' grid, whose nodes alone are kept:
  // through each point's own stencil (the MLS force of the ROM paper's Alg. 5).
  virtual void particles_to_grid(const Exec& exec, const mpm::ParticleView& points, const mpm::GridView& grid,
                                 const mpm::StepParams& step) {
    mpm::particle_to_grid_active_nodes(exec, points, grid, step, live_count());
  }
  // The points whose stencils G2P at the samples reads, the samples' grid built of them (stencil_points_per_sample()
  // a sample): the samples themselves.
  virtual Vec3Planes<const float> sample_stencil_points(const SampleSet& samples) const { return samples.x(); }
  virtual Index stencil_points_per_sample() const { return 1; }
  // G2P at the samples: their velocities and trial positions for the projection.
  virtual void grid_to_samples(const Exec& exec, SampleSet& samples, const mpm::GridView& grid,
                               const mpm::StepParams& step) {
    mpm::grid_to_particle(exec, samples.points().view(), grid, step);
  }

  // The positions of the last build's points that g gave and P2G reads at their own places (they must lie
  // inside the domain; the substep moves them there when they do not): none for Eulerian points, which lie
  // in cells by construction.
  virtual Vec3Planes<float> material_positions() = 0;

  // The last build's points as P2G's failure slot indexes them (mpm::note_failed_points keeps the one a slot
  // names), and how a report names such a point.
  virtual mpm::PointSource failure_source() const = 0;
  virtual std::string describe(const mpm::FailedPoint& point) const = 0;
  // The points of material_positions() as its domain check indexes them, and how a report names one: the
  // failure source's unless the quadrature places other points than those it reports P2G's failures at.
  virtual mpm::PointSource outside_source() const { return failure_source(); }
  virtual std::string describe_outside(std::int64_t point) const { return fmt::format("material point {}", point); }

  // The points of the last build (Eulerian: every point inverted, inside the body or not; counted on the
  // device, so this is a download).
  virtual Index last_count(const Exec& exec) const = 0;

  // Whether a build around `samples` samples runs on the device alone (no round trip: a CUDA graph can hold it).
  virtual bool builds_on_device(Index samples) const = 0;
  // Adds `builds` builds to what build() keeps on the host besides its launches: those a replayed graph ran,
  // or, negative, those a failed capture's host code counted but no launch ran.
  virtual void account_builds(int builds) { (void)builds; }

  // The CFL step's length for a grid of cell `dx`: the cell, unless the quadrature integrates nodes of smaller
  // elements.
  virtual float cfl_length(float dx) const { return dx; }
  // The factor on the stiffness at rest that the last build's points had at most (one value on the device,
  // written by P2G), which the CFL step's wave speed takes its square root of; empty: 1, always.
  virtual Span<const float> stiffening() { return {}; }
};

class LagrangianQuadrature final : public ReducedQuadrature {
 public:
  // `search`: the samples' neighbours among the material points; otherwise every material point.
  LagrangianQuadrature(const Exec& exec, const ReferenceBody& reference, int latent, float dx, bool search);

  // Searching, the neighbours are counted on the device: the view's count is every material point's, a bound
  // on them, and live_count() says how many there are (no round trip, so a CUDA graph holds the build).
  mpm::ParticleView build(const Exec& exec, const DeformationMap& map, const SampleSet& samples, Span<const float> xhat,
                          Span<const float> vhat) override;
  Span<const std::int64_t> live_count() const override { return neighbours_; }
  Vec3Planes<float> material_positions() override;
  mpm::PointSource failure_source() const override;
  std::string describe(const mpm::FailedPoint& point) const override;
  Index last_count(const Exec& exec) const override;  // searching, a download
  bool builds_on_device(Index) const override { return true; }
  // Searching, a build adds its count to a total on the device, in a launch a replay runs too.
  void account_builds(int builds) override {
    if (!search_) points_so_far_ += std::int64_t(builds) * points_.count;
  }

  bool searches_neighbours() const { return search_; }
  // Quadrature points summed over the builds so far (searching, a download).
  std::int64_t points_so_far(const Exec& exec) const;

 private:
  const ReferenceBody& reference_;
  int latent_;
  bool search_;
  float inverse_dx_;
  std::int64_t points_so_far_ = 0;
  QuadraturePoints points_;  // in reference order: every material point, or the neighbours in its first slots
  DeviceBuffer<float> dg_dxhat_;
  // The neighbour search: g's positions at every point, the points marked as neighbours, their indices and
  // count (the selector's slot, valid until its next call), the counts summed over the builds.
  DeviceBuffer<float> positions_;
  DeviceBuffer<std::int32_t> marked_, index_;
  Span<const std::int64_t> neighbours_;
  DeviceBuffer<std::int64_t> neighbours_so_far_;
  rom::SampleNeighbourhood neighbourhood_;
  IndexSelector select_;
};

// Every material point a quadrature point through its particle domain, the corners placed by g: the transfer
// of the full-order step on particle domains (kernels/mpm/particle_domains.h), so that a map trained on such
// data runs with the discretisation that made it. Every material point must have a domain. The corners of
// the whole body are decoded each substep (a point's neighbours through shared corners reach far: no search).
class DomainQuadrature final : public ReducedQuadrature {
 public:
  // `domains`: the reference body's (mpm::ParticleInit::domains), `point_domain` each material point's.
  // `enrichment_threshold`: the full-order step's (FullOrderConfig), whose corners of badly deformed domains
  // integrate on their own each substep (dynamic enrichment); 0: none.
  DomainQuadrature(const Exec& exec, const ReferenceBody& reference, const mpm::DomainInit& domains,
                   const std::vector<std::int32_t>& point_domain, int latent, float enrichment_threshold);

  mpm::ParticleView build(const Exec& exec, const DeformationMap& map, const SampleSet& samples, Span<const float> xhat,
                          Span<const float> vhat) override;
  // Through the domains' corners: the enrichment marked, particles_to_corners, then the corners' stencils.
  void particles_to_grid(const Exec& exec, const mpm::ParticleView& points, const mpm::GridView& grid,
                         const mpm::StepParams& step) override;
  // The corners of the samples' domains (8 a sample), which their velocities are gathered through.
  Vec3Planes<const float> sample_stencil_points(const SampleSet& samples) const override;
  Index stencil_points_per_sample() const override { return mpm::kDomainCorners; }
  void grid_to_samples(const Exec& exec, SampleSet& samples, const mpm::GridView& grid,
                       const mpm::StepParams& step) override;
  // The corners, which P2G places on the grid.
  Vec3Planes<float> material_positions() override { return domains_.view().x; }
  mpm::PointSource failure_source() const override;
  std::string describe(const mpm::FailedPoint& point) const override;
  mpm::PointSource outside_source() const override;
  std::string describe_outside(std::int64_t corner) const override;
  Index last_count(const Exec&) const override { return points_.count; }
  bool builds_on_device(Index) const override { return true; }
  void account_builds(int builds) override { points_so_far_ += std::int64_t(builds) * points_.count; }
  std::int64_t points_so_far() const { return points_so_far_; }
  Index corner_count() const { return domains_.corner_count(); }
  // Where corners may be enriched, as the full-order step: the shortest edge of a reference domain, if shorter.
  float cfl_length(float dx) const override;
  // Deformed domains are stiffer than at rest (mpm::domain_stiffening), as in the full-order step on them.
  Span<const float> stiffening() override { return domains_.view().stiffening; }

 private:
  bool enriches() const { return enrichment_threshold_ > 0.0f; }

  int latent_;
  float enrichment_threshold_;
  std::int64_t points_so_far_ = 0;
  mpm::ParticleDomains domains_;  // the corners' decoded positions and velocities, and P2G's accumulators
  DeviceBuffer<float> corner_X_;  // the corners' reference positions (3 planes)
  DeviceBuffer<float> corner_dg_dxhat_;
  DeviceBuffer<std::int32_t> point_domain_;
  QuadraturePoints points_;             // every material point, in reference order
  DeviceBuffer<float> sample_corners_;  // 8 a sample (3 planes of 8 m)
  Index sample_corner_count_ = 0;
};

// What the Eulerian quadrature needs of the scene besides the map.
struct EulerianSettings {
  rom::EulerianLattice lattice;     // dx, ℓ, the domain's cells, pruning
  rom::InversionOptions inversion;  // iterations and tolerance (m) of g's inversion
  std::vector<float> densities;     // ρ₀ per material (kg/m³)
  // Start the inversion of a point whose place was inverted in the last build from that solution
  // (kernels/rom/eulerian_warm_start.h) instead of g linearised at the cell's sample.
  bool warm_start = true;
};

class EulerianQuadrature final : public ReducedQuadrature {
 public:
  // `reference`: the material points in the reference configuration, which define the body (an
  // occupancy grid as fine as the finest sampling) that Eulerian points must fall in.
  EulerianQuadrature(const Exec& exec, const mpm::ParticleInit& reference, EulerianSettings settings);

  mpm::ParticleView build(const Exec& exec, const DeformationMap& map, const SampleSet& samples, Span<const float> xhat,
                          Span<const float> vhat) override;
  Vec3Planes<float> material_positions() override { return {}; }
  mpm::PointSource failure_source() const override;
  std::string describe(const mpm::FailedPoint& point) const override;
  Index last_count(const Exec& exec) const override;
  bool builds_on_device(Index samples) const override {
    return rom::SampleNeighbourhood::counts_on_device(samples, settings_.lattice);
  }
  // The points used, of the inverted ones: selected on the device and counted there.
  Span<const std::int64_t> live_count() const override { return used_count_; }

  // The running totals over the builds (a download).
  rom::QuadratureTally tally(const Exec& exec) const { return tally_.to_host(exec.stream)[0]; }

 private:
  EulerianSettings settings_;
  DeviceBuffer<std::int32_t> occupancy_cells_;
  rom::ReferenceOccupancy occupancy_;
  DeviceBuffer<float> densities_;
  DeviceBuffer<rom::QuadratureTally> tally_;
  QuadraturePoints points_;  // every point inverted: the first point_count_[0] of its slots
  Span<const std::int64_t> point_count_;
  QuadraturePoints used_;  // those inside the body, gathered for P2G: the first used_count_[0] of them
  Span<const std::int64_t> used_count_;
  // Refilled every build, grown to the largest count so far (an allocation on CUDA synchronises).
  DeviceBuffer<std::int32_t> used_index_;
  DeviceBuffer<std::int32_t> inversion_iterations_, map_evaluations_, jacobian_evaluations_;
  DeviceBuffer<float> guesses_, guess_jacobians_;  // each point's first X and ∂g/∂X there
  DeviceBuffer<std::uint64_t> place_cells_;        // each point's place: its cell and index in the cell
  DeviceBuffer<std::int32_t> place_subs_;
  // The last build's places, statuses, solutions (X, F, v) and x̂, v̂, kept for the next build's warm starts.
  DeviceBuffer<std::uint64_t> last_cells_;
  DeviceBuffer<std::int32_t> last_subs_, last_status_;
  DeviceBuffer<float> last_X_, last_v_, last_F_, last_xhat_, last_vhat_;
  DeviceBuffer<std::int64_t> last_point_count_;
  Index last_count_ = -1;  // the last build's slots (a bound on its points); −1: no build yet

  // The last build's points as warm starts read them.
  rom::Inversions last_inversions() const;
  // Keeps this build's points (in its `count` slots) and x̂, v̂ for the next build.
  void keep_for_warm_starts(const Exec& exec, Index count, Span<const float> xhat, Span<const float> vhat);
  rom::SampleNeighbourhood neighbourhood_;
  IndexSelector select_;
};

}  // namespace romp::engine
