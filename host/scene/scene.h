// Scene: the resolved content of a scene file (SI units, every default filled in, formulas evaluated).
// The parser builds it; scene_setup turns it into particles and a FullOrderConfig.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <optional>

#include "host/scene/sweep.h"
#include "kernels/material/material.h"
#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"
#include "kernels/mpm/collider.h"
#include "kernels/mpm/domain_config.h"

namespace romp::scene {

enum class ShapeType { Box, Sphere, Cylinder, Capsule, Mesh };

// A solid region: the body of an object, a Dirichlet region or a poke region.
struct ShapeSpec {
  ShapeType type = ShapeType::Box;
  Vec3<double> center = Vec3<double>::zero();        // box, sphere, cylinder, mesh (its bounding-box centre)
  Vec3<double> size = Vec3<double>::zero();          // box: full extents along its local axes
  Mat3<double> rotation = Mat3<double>::identity();  // box, mesh: local-to-world
  double radius = 0.0;                               // sphere, cylinder, capsule
  double height = 0.0;                               // cylinder: full length along `axis`
  Vec3<double> axis = Vec3<double>(0.0, 1.0, 0.0);   // cylinder (unit)
  Vec3<double> a = Vec3<double>::zero(), b = Vec3<double>::zero();  // capsule segment
  std::string mesh_file;     // mesh: absolute path (resolved against the scene's folder)
  double mesh_extent = 0.0;  // mesh: the largest side of its bounding box after scaling
};

enum class SamplingMethod { Lattice, JitteredLattice, PoissonDisk };

struct SamplingSpec {
  SamplingMethod method = SamplingMethod::Lattice;
  std::int32_t per_cell = 2;  // particles per grid cell per dimension
  double jitter = 1.0;        // jittered lattice: displacement up to ±jitter h / 2
  std::uint64_t seed = 0;
};

struct MaterialSpecification {
  std::string name;
  material::MaterialModel model = material::MaterialModel::FixedCorotated;
  double density = 1000.0;      // kg/m^3
  double youngs_modulus = 1e5;  // Pa
  double poissons_ratio = 0.3;
  double yield_stress = 0.0;     // von Mises (Pa)
  double friction_angle = 30.0;  // Drucker–Prager (degrees)
  double cohesion = 0.0;         // Drucker–Prager
  double min_stretch = 0.1;      // inversion handling: stress sees principal stretches >= this (0: off); not fluids
  std::string neural_law;        // MaterialModel::Neural: the law file (absolute path), from `neural = "law.h5"`
  // Where the scene names the law ("file:line:column: materials.NAME.neural"): the parser checks only that
  // it is a law file, so an error in the law itself, found where the run is set up, is located there.
  std::string neural_law_source;
  double strength_off_from = 0.0, strength_off_until = 0.0;  // s; no stiffness in between (engine::MaterialSpec)
};

struct ObjectSpec {
  std::string name;
  std::int32_t material = 0;  // index into Scene::materials
  ShapeSpec shape;            // unless the particles come from `points_file`
  SamplingSpec sampling;
  // Particles read from a file instead of sampled from `shape`: a PLY point cloud (x, y, z; optional vx,
  // vy, vz and volume per point) or a romp snapshot (X, volume0 and frame `points_frame`'s x and v), as
  // an absolute path. Each point is a particle of volume `particle_volume` (m³) where the file gives none.
  std::string points_file;
  std::int64_t points_frame = 0;
  double particle_volume = 0.0;
  // The initial velocity: velocity + velocity_formulas(x) + angular_velocity × (x − centre of mass); a
  // component's formula (of the parameters and the particle's position x, y, z at t = 0, m) where it has
  // one, empty where `velocity` holds it. APIC particles start with C = the gradient of that field.
  Vec3<double> velocity = Vec3<double>::zero();
  std::array<std::string, 3> velocity_formulas;
  Vec3<double> angular_velocity = Vec3<double>::zero();  // rad/s about the sampled body's centre of mass
  bool domains = false;  // hexahedral particle domains (lattice sampling only): no numerical fracture
};

struct ColliderSpecification {
  // As mpm::ColliderState: a plane's solid is local y < 0, a cylinder's axis is local y.
  mpm::ColliderShape shape = mpm::ColliderShape::HalfSpace;
  Vec3<double> center = Vec3<double>::zero();
  Mat3<double> rotation = Mat3<double>::identity();
  Vec3<double> half_extents = Vec3<double>::zero();
  mpm::ContactType contact = mpm::ContactType::Sticky;
  double friction = 0.0;
  Vec3<double> velocity = Vec3<double>::zero();
  Vec3<double> angular_velocity = Vec3<double>::zero();
  double end = std::numeric_limits<double>::infinity();  // s; the collider is gone from then on
};

// Particles inside `region` at t = 0 (first matching group wins) follow a prescribed rigid motion.
struct DirichletGroupSpec {
  std::string name;
  ShapeSpec region;
  Vec3<double> velocity = Vec3<double>::zero();
  Vec3<double> angular_velocity = Vec3<double>::zero();
  Vec3<double> pivot = Vec3<double>::zero();             // a point on the rotation axis at t = 0
  double end = std::numeric_limits<double>::infinity();  // s; the particles are released then
};

// An acceleration on the particles inside a box or sphere during [start, end): a poke.
struct PokeSpec {
  ShapeSpec region;  // box (axis-aligned) or sphere
  Vec3<double> acceleration = Vec3<double>::zero();
  double start = 0.0, end = 0.0;
};

// A surface traction (force per reference area) on the particles inside `region` at t = 0 (the first
// traction whose region holds a particle wins), during [start, end): each particle carries the traction
// times V₀^(2/3), its share of the loaded surface when the region holds one layer of the body's particles.
struct TractionSpecification {
  std::string name;
  ShapeSpec region;                              // box, sphere, cylinder or capsule
  Vec3<double> traction = Vec3<double>::zero();  // Pa
  double start = 0.0;
  double end = std::numeric_limits<double>::infinity();
};

// Particles inside `region` while start <= t < end lose their domains for good (mpm::release_domains).
struct DomainReleaseSpecification {
  ShapeSpec region;  // box (axis-aligned) or sphere
  double start = 0.0;
  double end = std::numeric_limits<double>::infinity();
};

struct OutputSpec {
  std::string file;  // snapshot path (.h5)
  std::vector<std::string> fields{"x", "v", "F", "C"};
  bool ply = false;
};

// The domain [0, size] per axis in cells of side dx, its walls, gravity and time stepping are the
// mpm::DomainConfig every simulation shares; the rest is the scene's own.
struct Scene : mpm::DomainConfig<double> {
  std::string name, description;
  std::string mode = "full-order";
  Vec3<double> domain_size = Vec3<double>::zero();
  // Time.
  double end_time = 0.0, frame_rate = 0.0;
  std::int64_t frame_count = 0;  // frames after the initial one: end_time × frame_rate
  // Solver.
  std::string transfer = "apic";
  std::string integrator = "explicit";
  double flip_alpha = 0.95;
  double enrichment = 0.6;  // particle domains: deformation quality at or below which corners are enriched
  std::vector<MaterialSpecification> materials;
  std::vector<ObjectSpec> objects;
  std::vector<ColliderSpecification> colliders;
  std::vector<DirichletGroupSpec> dirichlet;
  std::vector<PokeSpec> pokes;
  std::vector<TractionSpecification> tractions;
  std::vector<DomainReleaseSpecification> domain_releases;
  OutputSpec output;
  // The parameters the formulas saw (a sweep member's values), in declaration-independent name order.
  std::map<std::string, double> parameters;
  // The whole scene as resolved TOML: what `romp check` prints and what outputs store.
  std::string resolved_text;
  std::string source_file;
  std::optional<SweepSpec> sweep;
};

}  // namespace romp::scene
