// One explicit MLS-MPM substep as three stages over a sparse grid: P2G, grid update, G2P (and the
// plastic return map when the scene has plastic materials). The host composes them; see FullOrderSim.
#pragma once

#include <cmath>
#include <cstdint>

#include "kernels/core/atomic.h"
#include "kernels/core/exec.h"
#include "kernels/core/span.h"
#include "kernels/material/material.h"
#include "kernels/math/finite.h"
#include "kernels/math/mat3.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/mpm/collider.h"
#include "kernels/mpm/domain_walls.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"

namespace romp::mpm {

enum class Transfer : std::int32_t {
  Apic = 0,     // MLS-MPM with APIC affine momentum (Hu et al. 2018); conserves angular momentum
  PicFlip = 1,  // PIC/FLIP blend of velocities; the affine matrix is kept only as the velocity gradient
};

// A prescribed rigid motion over the substep [t, t + dt]: v(x) = linear + angular × (x − pivot(t)).
struct RigidMotion {
  Vec3<float> pivot;  // at the start of the substep
  Vec3<float> linear_velocity;
  Vec3<float> angular_velocity;
  Mat3<float> step_rotation;  // exp(dt [angular]×), so rotating particles stay on their circles

  ROMP_HD Vec3<float> velocity_at(const Vec3<float>& x) const {
    return linear_velocity + cross(angular_velocity, x - pivot);
  }
  // Where the material point at x (at the start of the substep) is at its end.
  ROMP_HD Vec3<float> moved(const Vec3<float>& x, float dt) const {
    return pivot + dt * linear_velocity + step_rotation * (x - pivot);
  }
  // moved(x, dt) − x, formed without subtracting positions (which would cancel most of its digits).
  ROMP_HD Vec3<float> displacement(const Vec3<float>& x, float dt) const {
    const Vec3<float> arm = x - pivot;
    return dt * linear_velocity + (step_rotation * arm - arm);
  }
  // A particle of the group over the substep: x and F carried along, v the rigid field at the old x,
  // C = [ω]× its velocity gradient.
  ROMP_HD void carry(float dt, Vec3<float>& x, Vec3<float>& v, Mat3<float>& C, Mat3<float>& F) const {
    const Vec3<float>& w = angular_velocity;
    v = velocity_at(x);
    C = Mat3<float>(0.0f, -w[2], w[1], w[2], 0.0f, -w[0], -w[1], w[0], 0.0f);
    x = moved(x, dt);
    F = step_rotation * F;
  }
};

enum class RegionShape : std::int32_t { Box = 0, Sphere = 1 };

// A fixed region of space: an axis-aligned box or a sphere.
struct Region {
  RegionShape shape = RegionShape::Box;
  Vec3<float> center;
  Vec3<float> half_extents;  // box half sizes; a sphere's radius is half_extents[0]

  ROMP_HD bool contains(const Vec3<float>& x) const {
    const Vec3<float> d = x - center;
    if (shape == RegionShape::Sphere) return squared_norm(d) <= half_extents[0] * half_extents[0];
    return math::abs(d[0]) <= half_extents[0] && math::abs(d[1]) <= half_extents[1] &&
           math::abs(d[2]) <= half_extents[2];
  }
};

// An acceleration applied to the particles inside a region (a poke), active for this substep.
struct RegionLoad : Region {
  Vec3<float> acceleration;  // m/s^2
};

// Stages that can fail, and the slot each records its first offending particle or node in.
enum class Stage : std::int32_t { P2G = 0, GridUpdate = 1, G2P = 2, Plasticity = 3 };
inline constexpr int kStageCount = 4;
inline constexpr std::int64_t kNoFailure = INT64_MAX;

struct StepParams {
  float dt = 0.0f;
  Vec3<float> gravity = Vec3<float>::zero();
  Transfer transfer = Transfer::Apic;
  float flip_alpha = 0.95f;    // FLIP share of the PIC/FLIP blend
  Domain domain;               // the box, its wall bands and their contact
  float wall_friction = 0.0f;  // Coulomb friction of Separate walls (resolve_walls)
  Span<const material::MaterialParams<float>> materials;
  Span<const ColliderState> colliders;
  Span<const RigidMotion> dirichlet;
  Span<const RegionLoad> loads;
  // Per traction (ParticleView::traction): its traction now, Pa per reference area, 0 while inactive.
  Span<const Vec3<float>> tractions;
  Span<std::int64_t> first_failure;  // kStageCount slots, kNoFailure until a stage sees a non-finite value
  // Where moved particles record the largest speed they store (the next CFL step's), as float bits >= 0 that
  // start at 0; empty: not recorded.
  Span<float> largest_speed;
  // The first Piola stress of every particle whose material is MaterialModel::Neural, in this
  // substep's particle order (the host evaluates it after the sort); empty when no material is.
  Mat3Planes<const float> host_stress;
};

// The force of particle p's surface traction (N): the traction times the particle's share of the loaded
// reference surface, V₀^(2/3) (one layer of a lattice sampling: h² each); 0 without one.
ROMP_HD inline Vec3<float> traction_force(const StepParams& step, const ParticleView& particles, Index p) {
  if (particles.traction.empty() || particles.traction[p] == kNoTraction) return Vec3<float>::zero();
  const float side = std::cbrt(particles.volume0[p]);
  return (side * side) * step.tractions[particles.traction[p]];
}

// The first Piola stress of particle p at its F: the host's value for a neural material, the
// model's P(F) for every other (and NaN for a neural one when the host supplied none, host_evaluated.h).
ROMP_HD inline Mat3<float> particle_first_piola(const StepParams& step, const material::MaterialParams<float>& params,
                                                Index p, const Mat3<float>& F) {
  if (params.model == material::MaterialModel::Neural && step.host_stress.count() > 0) return step.host_stress.load(p);
  return material::first_piola(params, F);
}

void particle_to_grid(const Exec& exec, const ParticleView& particles, const GridView& grid, const StepParams& step);
// P2G into a grid built from other points than these particles: only the shares that fall in its active
// blocks are added, the rest dropped. A reduced substep builds its grid from the samples, whose nodes alone
// G2P reads; the grid update is node by node, so the dropped shares change no node the samples read.
// `live`, where given, is a count on exec's backend: only the first live[0] of particles.count (a bound) add.
void particle_to_grid_active_nodes(const Exec& exec, const ParticleView& particles, const GridView& grid,
                                   const StepParams& step, Span<const std::int64_t> live = {});
// The same P2G by grid block (p2g_tiled.cu): each block's particles add into a local tile of nodes
// that reaches the grid once. `block_starts` and `sorted_keys` are the runs and the particles' block keys of
// the last ParticleSet::sort_by_block, which may be several substeps old: particles that have left their
// run's block since are added by a second launch, skipped when `sorted_at_these_positions` (the sort ran on
// the particles' current positions). The result equals particle_to_grid's up to float rounding.
void particle_to_grid_tiled(const Exec& exec, const ParticleView& particles, const GridView& grid,
                            const StepParams& step, Span<const std::int32_t> block_starts,
                            Span<const std::uint64_t> sorted_keys, bool sorted_at_these_positions);
void update_grid(const Exec& exec, const GridView& grid, const StepParams& step);
// What G2P checks for a grid that serves several substeps (SparseGrid::rebuild_around_blocks): each particle's
// block key at the last sort, and a float set to 1 when a particle's new stencil has left the blocks around
// it, so that the next substep sorts and rebuilds. Empty: no check (the grid is rebuilt every substep).
struct GridCoverage {
  Span<const std::uint64_t> sorted_keys;
  Span<float> left;
};
// `return_map`: each particle G2P moves (outside a Dirichlet group) also takes project_plasticity's return map
// at its new F, the same arithmetic in the same pass (one pass less over F and the plastic state). Particles in
// a domain are left to corners_to_particles, and so to a project_plasticity pass after it.
void grid_to_particle(const Exec& exec, const ParticleView& particles, const GridView& grid, const StepParams& step,
                      const GridCoverage& coverage = {}, bool return_map = false);
// The return map of each plastic material, on particles not in a Dirichlet group.
void project_plasticity(const Exec& exec, const ParticleView& particles, const StepParams& step);

// Records the first particle whose F is not finite as `stage`'s failure (after a stage that changed F
// outside the kernels above, such as a host-evaluated plastic law).
void record_non_finite_deformation(const Exec& exec, const ParticleView& particles, const StepParams& step,
                                   Stage stage);

// Stores a particle's new state, recording it as G2P's failure when any of it is not finite, and its speed in
// step.largest_speed: the end of grid_to_particle and of corners_to_particles, so no pass of its own reads the
// velocities again for the CFL step. `F_stored`: what is stored of F where G2P changed it further (the return
// map), G2P's own F being the one checked.
ROMP_HD inline void store_moved_particle(const ParticleView& particles, const StepParams& step, Index p,
                                         const Vec3<float>& x, const Vec3<float>& v, const Mat3<float>& C,
                                         const Mat3<float>& F, const Mat3<float>& F_stored) {
  if (!(is_finite(x) && is_finite(v) && is_finite(F) && is_finite(C)))
    atomic_min(&step.first_failure[int(Stage::G2P)], std::int64_t(p));
  particles.x.store(p, x);
  particles.v.store(p, v);
  particles.C.store(p, C);
  particles.F.store(p, F_stored);
  // Speeds are >= 0, so the float max of their values is the max of the speeds.
  if (!step.largest_speed.empty()) atomic_max(&step.largest_speed[0], norm(v));
}
ROMP_HD inline void store_moved_particle(const ParticleView& particles, const StepParams& step, Index p,
                                         const Vec3<float>& x, const Vec3<float>& v, const Mat3<float>& C,
                                         const Mat3<float>& F) {
  store_moved_particle(particles, step, p, x, v, C, F, F);
}

// The largest particle speed (for the CFL condition before a first substep has recorded it), reduced in
// `slot` (one element of the backend's memory, kept by the caller so that a substep allocates nothing);
// synchronises with the host.
float max_particle_speed(const Exec& exec, const ParticleView& particles, Span<float> slot);

}  // namespace romp::mpm
