// Scene → FullOrderConfig and particles.
#include "host/scene/scene_setup.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "host/geometry/lattice_domains.h"
#include "host/geometry/mesh_io.h"
#include "host/geometry/sampling.h"
#include "host/geometry/triangle_mesh.h"
#include "host/scene/expression.h"
#include "host/scene/material_library.h"
#include "host/scene/point_file.h"
#include "host/scene/toml_reader.h"

namespace romp::scene {
namespace {

Vec3<float> to_float(const Vec3<double>& v) { return Vec3<float>(float(v[0]), float(v[1]), float(v[2])); }

Mat3<float> to_float(const Mat3<double>& m) {
  Mat3<float> f;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) f(i, j) = float(m(i, j));
  return f;
}

// A poke's or domain release's region (a sphere or an axis-aligned box) for the kernels.
mpm::Region to_region(const ShapeSpec& shape) {
  mpm::Region region;
  region.shape = shape.type == ShapeType::Sphere ? mpm::RegionShape::Sphere : mpm::RegionShape::Box;
  region.center = to_float(shape.center);
  region.half_extents =
      shape.type == ShapeType::Sphere ? Vec3<float>::constant(float(shape.radius)) : to_float(shape.size * 0.5);
  return region;
}

// An object's initial velocity field v(x) = v0 + f(x) + ω × (x − c) (ObjectSpec), and its gradient
// ∂v_i/∂x_j, the affine velocity C an APIC particle starts with (without it a spinning or shearing body
// starts with the wrong affine momentum).
class InitialVelocity {
 public:
  InitialVelocity(const ObjectSpec& object, const Scene& scene, const Vec3<double>& center)
      : object_(object), center_(center), step_(1e-4 * scene.dx) {
    for (int a = 0; a < 3; ++a)
      if (!object.velocity_formulas[std::size_t(a)].empty())
        formulas_[std::size_t(a)].emplace(object.velocity_formulas[std::size_t(a)], scene.parameters,
                                          std::vector<std::string>{"x", "y", "z"});
  }

  Vec3<double> at(const Vec3<double>& x) const {
    return object_.velocity + field(x) + cross(object_.angular_velocity, x - center_);
  }

  // The rotation's gradient is exact; the formulas' is a central difference (step 1e-4 dx: error
  // ~1e-8 dx² of the third derivative, far below float's resolution of C).
  Mat3<double> gradient(const Vec3<double>& x) const {
    const Vec3<double>& w = object_.angular_velocity;
    Mat3<double> g = Mat3<double>::zero();
    g(0, 1) = -w[2], g(0, 2) = w[1], g(1, 0) = w[2], g(1, 2) = -w[0], g(2, 0) = -w[1], g(2, 1) = w[0];
    if (!varies()) return g;
    for (int j = 0; j < 3; ++j) {
      Vec3<double> ahead = x, behind = x;
      ahead[j] += step_;
      behind[j] -= step_;
      const Vec3<double> difference = (field(ahead) - field(behind)) * (0.5 / step_);
      for (int i = 0; i < 3; ++i) g(i, j) += difference[i];
    }
    return g;
  }

  bool rotates_or_varies() const { return varies() || !(object_.angular_velocity == Vec3<double>::zero()); }

 private:
  bool varies() const { return formulas_[0] || formulas_[1] || formulas_[2]; }
  Vec3<double> field(const Vec3<double>& x) const {
    Vec3<double> f = Vec3<double>::zero();
    const std::vector<double> position{x[0], x[1], x[2]};
    for (int a = 0; a < 3; ++a)
      if (formulas_[std::size_t(a)]) f[a] = (*formulas_[std::size_t(a)])(position);
    return f;
  }

  const ObjectSpec& object_;
  Vec3<double> center_;
  double step_;
  std::array<std::optional<Formula>, 3> formulas_;
};

engine::FullOrderConfig engine_config(const Scene& scene) {
  engine::FullOrderConfig c;
  static_cast<mpm::DomainConfig<float>&>(c) = scene.converted<float>();
  c.transfer = scene.transfer == "apic" ? mpm::Transfer::Apic : mpm::Transfer::PicFlip;
  c.flip_alpha = float(scene.flip_alpha);
  c.enrichment_threshold = float(scene.enrichment);
  c.integrator = scene.integrator == "implicit" ? engine::Integrator::Implicit : engine::Integrator::Explicit;
  for (const MaterialSpecification& m : scene.materials) c.materials.push_back(scene::to_material_spec(m));
  for (const ColliderSpecification& s : scene.colliders) {
    mpm::ColliderState state;
    state.shape = s.shape;
    state.contact = s.contact;
    state.friction = float(s.friction);
    state.center = to_float(s.center);
    state.rotation = to_float(s.rotation);
    state.half_extents = to_float(s.half_extents);
    state.linear_velocity = to_float(s.velocity);
    state.angular_velocity = to_float(s.angular_velocity);
    c.colliders.push_back(engine::ColliderSpec{state, s.end});
  }
  for (const DirichletGroupSpec& g : scene.dirichlet)
    c.dirichlet.push_back(
        engine::DirichletSpec{to_float(g.pivot), to_float(g.velocity), to_float(g.angular_velocity), g.end});
  for (const PokeSpec& p : scene.pokes) {
    mpm::RegionLoad load;
    static_cast<mpm::Region&>(load) = to_region(p.region);
    load.acceleration = to_float(p.acceleration);
    c.loads.push_back(engine::RegionLoadSpec{load, p.start, p.end});
  }
  for (const TractionSpecification& t : scene.tractions)
    c.tractions.push_back(engine::TractionSpec{to_float(t.traction), t.start, t.end});
  for (const DomainReleaseSpecification& d : scene.domain_releases)
    c.domain_releases.push_back(engine::DomainReleaseSpec{to_region(d.region), d.start, d.end});
  return c;
}

geometry::SamplingSpec sampling_for(const SamplingSpec& s, double dx) {
  geometry::SamplingSpec g;
  g.method = s.method == SamplingMethod::Lattice           ? geometry::SamplingMethod::Lattice
             : s.method == SamplingMethod::JitteredLattice ? geometry::SamplingMethod::JitteredLattice
                                                           : geometry::SamplingMethod::PoissonDisk;
  g.per_cell = s.per_cell;
  g.dx = dx;
  g.jitter = s.jitter;
  g.seed = s.seed;
  return g;
}

// Particles must keep their quadratic stencil inside the domain: at least one cell from each face.
void check_inside_domain(const Scene& scene, const ObjectSpec& object, const std::vector<Vec3<double>>& points) {
  for (const Vec3<double>& p : points)
    for (int a = 0; a < 3; ++a) {
      const double low = scene.dx, high = scene.domain_size[a] - scene.dx;
      if (!(p[a] >= low && p[a] <= high))  // a non-finite position too (a point file's)
        throw SceneError(fmt::format(
            "{}: objects '{}': a particle at {} lies outside the domain's interior [{}, {}] along axis {} (or is "
            "not finite; the "
            "outermost cell is reserved for the stencil); move or shrink the object, or enlarge [domain] size",
            scene.source_file, object.name, geometry::describe_point(p), low, high, a));
    }
}

}  // namespace

geometry::Shape make_shape(const ShapeSpec& s) {
  switch (s.type) {
    case ShapeType::Box: return geometry::Box{s.center, s.size * 0.5, s.rotation};
    case ShapeType::Sphere: return geometry::Sphere{s.center, s.radius};
    case ShapeType::Cylinder: return geometry::Cylinder{s.center, s.axis, s.radius, 0.5 * s.height};
    case ShapeType::Capsule: return geometry::Capsule{s.a, s.b, s.radius};
    case ShapeType::Mesh:
      return geometry::MeshSolid(
          geometry::fit_to(geometry::load_mesh(s.mesh_file), s.mesh_extent, s.center, s.rotation));
  }
  throw Error("unknown shape type");
}

SceneSetup build_scene(const Scene& scene) {
  SceneSetup setup = sample_scene(scene);
  setup.config = engine_config(scene);
  return setup;
}

SceneSetup sample_scene(const Scene& scene) {
  SceneSetup setup;
  std::vector<geometry::Shape> regions, traction_regions;
  for (const DirichletGroupSpec& group : scene.dirichlet) regions.push_back(make_shape(group.region));
  for (const TractionSpecification& traction : scene.tractions) traction_regions.push_back(make_shape(traction.region));
  std::vector<std::int32_t> traction_of;  // per particle, as the objects are appended

  // Each particle's initial C (its velocity field's gradient), kept as planes only when one is not 0.
  std::vector<std::pair<Index, Mat3<float>>> affine;
  for (const ObjectSpec& object : scene.objects) {
    std::optional<geometry::Shape> shape;
    geometry::SampledBody body;
    geometry::PointCloud cloud;  // an object read from a point file
    if (!object.points_file.empty()) {
      cloud = load_points(object, scene.source_file);
      body.points = cloud.x;
      body.particle_volume = cloud.volume.front();
    } else {
      try {
        shape.emplace(make_shape(object.shape));
        body = geometry::sample(*shape, sampling_for(object.sampling, scene.dx));
      } catch (const SceneError&) {
        throw;
      } catch (const Error& error) {
        throw SceneError(fmt::format("{}: objects '{}': {}", scene.source_file, object.name, error.what()));
      }
    }
    check_inside_domain(scene, object, body.points);
    const Index first = setup.particles.count();
    const MaterialSpecification& material = scene.materials[std::size_t(object.material)];
    geometry::append_body(setup.particles, body, material.density, object.material);
    // A point file's own volumes, each point's.
    for (std::size_t i = 0; i < cloud.volume.size(); ++i) {
      setup.particles.volume0[std::size_t(first) + i] = float(cloud.volume[i]);
      setup.particles.mass[std::size_t(first) + i] = float(material.density * cloud.volume[i]);
    }
    if (object.domains) {
      const double spacing = sampling_for(object.sampling, scene.dx).spacing();
      const Index first_domain = setup.particles.domains.count();
      geometry::append_lattice_domains(setup.particles, first, body, spacing);
      if (const auto* solid = std::get_if<geometry::MeshSolid>(&shape->variant()))
        setup.embedded_meshes.push_back(
            geometry::embed_mesh(solid->mesh(), object.name, setup.particles.domains, first_domain, spacing));
    }
    setup.particles_per_object.push_back(setup.particles.count() - first);

    // The initial velocity about the body's centre of mass (its particles' masses go as their volumes).
    Vec3<double> center = Vec3<double>::zero();
    double volume = 0.0;
    for (std::size_t i = 0; i < body.points.size(); ++i) {
      const double share = cloud.volume.empty() ? 1.0 : cloud.volume[i];
      center += body.points[i] * share;
      volume += share;
    }
    center *= 1.0 / volume;
    const InitialVelocity velocity(object, scene, center);
    mpm::ParticleInit& init = setup.particles;
    const Index n = init.count();
    for (std::size_t i = 0; i < body.points.size(); ++i) {
      const Index p = first + Index(i);
      const Vec3<double> v = velocity.at(body.points[i]) + (cloud.v.empty() ? Vec3<double>::zero() : cloud.v[i]);
      for (int a = 0; a < 3; ++a) {
        if (!std::isfinite(v[a]))
          throw SceneError(fmt::format("{}: objects '{}': velocity[{}] is {} at x = ({:.6g}, {:.6g}, {:.6g}) m",
                                       scene.source_file, object.name, a, v[a], body.points[i][0], body.points[i][1],
                                       body.points[i][2]));
        init.v[std::size_t(a * n + p)] = float(v[a]);
      }
      if (velocity.rotates_or_varies()) affine.emplace_back(p, to_float(velocity.gradient(body.points[i])));
      for (std::size_t g = 0; g < regions.size(); ++g)
        if (regions[g].contains(body.points[i])) {
          init.dirichlet_group[std::size_t(p)] = std::int32_t(g);
          break;
        }
      std::int32_t traction = mpm::kNoTraction;
      for (std::size_t t = 0; t < traction_regions.size() && traction == mpm::kNoTraction; ++t)
        if (traction_regions[t].contains(body.points[i])) traction = std::int32_t(t);
      traction_of.push_back(traction);
    }
  }
  if (!affine.empty()) {
    mpm::ParticleInit& init = setup.particles;
    const std::size_t n = std::size_t(init.count());
    init.C.assign(9 * n, 0.0f);
    for (const auto& [p, gradient] : affine)
      for (int k = 0; k < 9; ++k) init.C[std::size_t(k) * n + std::size_t(p)] = gradient(k / 3, k % 3);
  }
  if (!scene.tractions.empty()) {
    std::vector<Index> loaded(scene.tractions.size(), 0);
    for (const std::int32_t t : traction_of)
      if (t != mpm::kNoTraction) ++loaded[std::size_t(t)];
    for (std::size_t t = 0; t < loaded.size(); ++t)
      if (loaded[t] == 0)
        throw SceneError(fmt::format("{}: loads.tractions '{}': its region holds no particle at t = 0",
                                     scene.source_file, scene.tractions[t].name));
    setup.particles.traction = std::move(traction_of);
  }
  // The plastic state (J_p = 1, no plastic strain yet) where a material has a return map.
  for (const MaterialSpecification& m : scene.materials)
    if (m.model == material::MaterialModel::DruckerPrager || m.model == material::MaterialModel::VonMises) {
      const std::size_t n = std::size_t(setup.particles.count());
      setup.particles.plastic.assign(2 * n, 0.0f);
      std::fill(setup.particles.plastic.begin(), setup.particles.plastic.begin() + std::ptrdiff_t(n), 1.0f);
      break;
    }
  if (!setup.particles.domains.empty()) geometry::assign_corner_dirichlet_groups(setup.particles);
  return setup;
}

}  // namespace romp::scene
