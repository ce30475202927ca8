// Scene → FullOrderConfig and particles.
#include "host/scene/scene_setup.h"

#include <optional>
#include <variant>

#include <fmt/format.h>

#include "host/geometry/lattice_domains.h"
#include "host/geometry/mesh_io.h"
#include "host/geometry/sampling.h"
#include "host/geometry/triangle_mesh.h"
#include "host/scene/material_library.h"
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
      if (p[a] < low || p[a] > high)
        throw SceneError(fmt::format(
            "{}: objects '{}': a particle at {} lies outside the domain's interior [{}, {}] along axis {} (the "
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
  std::vector<geometry::Shape> regions;
  for (const DirichletGroupSpec& group : scene.dirichlet) regions.push_back(make_shape(group.region));

  for (const ObjectSpec& object : scene.objects) {
    std::optional<geometry::Shape> shape;
    geometry::SampledBody body;
    try {
      shape.emplace(make_shape(object.shape));
      body = geometry::sample(*shape, sampling_for(object.sampling, scene.dx));
    } catch (const SceneError&) {
      throw;
    } catch (const Error& error) {
      throw SceneError(fmt::format("{}: objects '{}': {}", scene.source_file, object.name, error.what()));
    }
    check_inside_domain(scene, object, body.points);
    const Index first = setup.particles.count();
    const MaterialSpecification& material = scene.materials[std::size_t(object.material)];
    geometry::append_body(setup.particles, body, material.density, object.material);
    if (object.domains) {
      const double spacing = sampling_for(object.sampling, scene.dx).spacing();
      const Index first_domain = setup.particles.domains.count();
      geometry::append_lattice_domains(setup.particles, first, body, spacing);
      if (const auto* solid = std::get_if<geometry::MeshSolid>(&shape->variant()))
        setup.embedded_meshes.push_back(
            geometry::embed_mesh(solid->mesh(), object.name, setup.particles.domains, first_domain, spacing));
    }
    setup.particles_per_object.push_back(setup.particles.count() - first);

    // Rigid initial velocity about the body's centre of mass (all its particles have one mass).
    Vec3<double> center = Vec3<double>::zero();
    for (const Vec3<double>& p : body.points) center += p;
    center *= 1.0 / double(body.points.size());
    mpm::ParticleInit& init = setup.particles;
    const Index n = init.count();
    for (std::size_t i = 0; i < body.points.size(); ++i) {
      const Index p = first + Index(i);
      const Vec3<double> v = object.velocity + cross(object.angular_velocity, body.points[i] - center);
      for (int a = 0; a < 3; ++a) init.v[std::size_t(a * n + p)] = float(v[a]);
      for (std::size_t g = 0; g < regions.size(); ++g)
        if (regions[g].contains(body.points[i])) {
          init.dirichlet_group[std::size_t(p)] = std::int32_t(g);
          break;
        }
    }
  }
  if (!setup.particles.domains.empty()) geometry::assign_corner_dirichlet_groups(setup.particles);
  return setup;
}

}  // namespace romp::scene
