// From a resolved Scene to what FullOrderSim takes: the engine configuration and the sampled particles.
#pragma once

#include <cstdint>
#include <vector>

#include "host/engine/full_order_sim.h"
#include "host/geometry/embedded_mesh.h"
#include "host/geometry/shape.h"
#include "host/scene/scene.h"
#include "kernels/mpm/particle_set.h"

namespace romp::scene {

struct SceneSetup {
  engine::FullOrderConfig config;
  mpm::ParticleInit particles;
  std::vector<Index> particles_per_object;  // in the order of Scene::objects
  // The surface of every mesh object with domains, riding in them (exported per frame as OBJ).
  std::vector<geometry::EmbeddedMesh> embedded_meshes;
};

// The solid a ShapeSpec describes (meshes are loaded and placed here).
geometry::Shape make_shape(const ShapeSpec& shape);

// Samples every object, sets initial velocities (ObjectSpec: v + f(x) + ω × (x − centre of mass)) and
// APIC's C (their gradient, where not 0), assigns Dirichlet groups (the first region that holds a
// particle at t = 0) and converts materials, colliders and loads. A body that reaches into the boundary margin or out
// of the domain is a SceneError naming the object.
SceneSetup build_scene(const Scene& scene);

// build_scene without the engine configuration (`config` left at its defaults): the particles alone,
// which is what `romp check` reports, loading no learned law and evaluating no network.
SceneSetup sample_scene(const Scene& scene);

}  // namespace romp::scene
