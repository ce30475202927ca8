// Sampling a shape into particles (lattice, jittered lattice, Poisson disk) and appending them to a ParticleInit.
#pragma once

#include <cstdint>
#include <vector>

#include "host/geometry/shape.h"
#include "kernels/math/vec3.h"
#include "kernels/mpm/particle_set.h"

namespace romp::geometry {

enum class SamplingMethod { Lattice, JitteredLattice, PoissonDisk };

// How densely a body is sampled: spacing h = dx / per_cell, one particle per h³ on average.
struct SamplingSpec {
  SamplingMethod method = SamplingMethod::Lattice;
  int per_cell = 2;     // particles per grid cell per dimension, >= 1
  double dx = 0.0;      // grid spacing
  double jitter = 1.0;  // JitteredLattice: displacement uniform in ±jitter·h/2 per axis, jitter in [0, 1]
  std::uint64_t seed = 0;

  double spacing() const { return dx / per_cell; }
};

// The Poisson-disk radius, in units of the spacing h, at which Bridson's algorithm (k = 30) leaves
// one point per h³ on average. Measured with poisson_disk_sample on a cube of side 70 r, seeds 1234,
// 1235 and 1236 (201,000 points each), counting the points more than 5 r from its faces: 0.5766 ±
// 0.0002 points per r³, so r = 0.5766^(1/3) h.
inline constexpr double kPoissonRadiusPerSpacing = 0.8323;

struct SampledBody {
  std::vector<Vec3<double>> points;
  double particle_volume = 0.0;  // every particle's share of the body's volume
};

// Particles filling `shape`:
//   Lattice: the points (i + 0.5) h of the global lattice anchored at the origin that lie inside, so
//     bodies sampled separately line up; each has volume h³.
//   JitteredLattice: each of those lattice points moved uniformly within ±jitter·h/2 per axis, kept
//     where it lands inside.
//   PoissonDisk: Bridson's algorithm over the shape's bounds at radius kPoissonRadiusPerSpacing·h,
//     kept where inside.
// For the last two the particles share the lattice's volume estimate (lattice points inside × h³),
// so a body's mass does not depend on the method. Throws romp::Error for an invalid spec, and,
// naming the shape and the spacing, when no particle falls inside.
SampledBody sample(const Shape& shape, const SamplingSpec& spec);

// Appends the particles at rest: mass density × particle_volume, volume0 particle_volume, the given
// material, no Dirichlet group. The position and velocity planes are rebuilt for the new count.
void append_body(mpm::ParticleInit& init, const SampledBody& body, double density, std::int32_t material);

// The particles of the axis-aligned box [low, high] alone, at rest, material 0: the common body of
// tests and benchmarks.
mpm::ParticleInit sample_box(const Vec3<float>& low, const Vec3<float>& high, const SamplingSpec& spec, double density);

}  // namespace romp::geometry
