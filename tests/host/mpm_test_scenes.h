// Small particle bodies and energy/momentum measures for the full-order MPM verification tests.
#pragma once

#include <cmath>
#include <vector>

#include "host/engine/full_order_sim.h"
#include "host/geometry/lattice_domains.h"
#include "host/geometry/sampling.h"
#include "kernels/material/material.h"
#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"

namespace romp::test {

// Particles of the global lattice of spacing dx / per_cell inside the box [low, high], at density rho.
inline mpm::ParticleInit lattice_box(const Vec3<float>& low, const Vec3<float>& high, float dx, int per_cell,
                                     float rho) {
  return geometry::sample_box(low, high, geometry::SamplingSpec{geometry::SamplingMethod::Lattice, per_cell, dx}, rho);
}

// lattice_box, every particle with its lattice cell as a hexahedral domain (corners shared).
inline mpm::ParticleInit lattice_box_with_domains(const Vec3<float>& low, const Vec3<float>& high, float dx,
                                                  int per_cell, float rho) {
  return geometry::sample_box_with_domains(
      low, high, geometry::SamplingSpec{geometry::SamplingMethod::Lattice, per_cell, dx}, rho);
}

inline Vec3<float> plane_vector(const std::vector<float>& planes, Index count, Index p) {
  return Vec3<float>(planes[p], planes[count + p], planes[2 * count + p]);
}

inline void set_plane_vector(std::vector<float>& planes, Index count, Index p, const Vec3<float>& value) {
  for (int a = 0; a < 3; ++a) planes[a * count + p] = value[a];
}

// A configuration with no gravity, no walls in reach, and one material.
inline engine::FullOrderConfig open_space_config(float dx, int cells, const engine::MaterialSpec& material) {
  engine::FullOrderConfig config;
  config.dx = dx;
  config.domain_cells = {cells, cells, cells};
  config.gravity = Vec3<float>::zero();
  config.materials = {material};
  return config;
}

}  // namespace romp::test
