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
#pragma once

#include <cstdint>
#include <string>

#include "host/engine/deformation_map.h"
#include "host/engine/quadrature_points.h"
#include "host/engine/sample_set.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/core/index_select.h"
#include "kernels/mpm/failed_points.h"
#include "kernels/mpm/particle_set.h"
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

  // The positions of the last build's material points, which g gave (they must lie inside the domain; the
  // substep moves them there when they do not): none for Eulerian points, which lie in cells by construction.
  virtual Vec3Planes<float> material_positions() = 0;

  // The last build's points as P2G's failure slot and the domain check of material_positions() index them
  // (mpm::note_failed_points keeps the one a slot names), and how a report names such a point.
  virtual mpm::PointSource failure_source() const = 0;
  virtual std::string describe(const mpm::FailedPoint& point) const = 0;

  // The points of the last build (Eulerian: every point inverted, inside the body or not; counted on the
  // device, so this is a download).
  virtual Index last_count(const Exec& exec) const = 0;

  // Whether a build around `samples` samples runs on the device alone (no round trip: a CUDA graph can hold it).
  virtual bool builds_on_device(Index samples) const = 0;
  // Adds `builds` builds to what build() keeps on the host besides its launches: those a replayed graph ran,
  // or, negative, those a failed capture's host code counted but no launch ran.
  virtual void account_builds(int builds) { (void)builds; }
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
