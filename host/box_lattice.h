// Particles on a regular lattice filling an axis-aligned box: the simplest sampling of a body.
#pragma once

#include <cstdint>

#include "kernels/math/vec3.h"
#include "kernels/mpm/particle_set.h"

namespace romp {

// Particles at the centres of the cells of a lattice of the given spacing filling [low, high), each
// with volume spacing³ and mass density × volume, at rest, of one material, in no Dirichlet group.
mpm::ParticleInit sample_box_lattice(const Vec3<float>& low, const Vec3<float>& high, float spacing, float density,
                                     std::int32_t material = 0);

}  // namespace romp
