// The mechanical energy of a full-order state: what stability checks and energy tests compare over time.
#pragma once

#include "host/engine/full_order_sim.h"
#include "kernels/math/vec3.h"

namespace romp::analysis {

// Kinetic + elastic + gravitational energy (J) of `sim`'s particles, `init` being the state it was
// built from (masses, volumes, materials). Heights are measured from `origin`, the zero of the
// gravitational potential. Reads the particles back to the host.
double mechanical_energy(engine::FullOrderSim& sim, const mpm::ParticleInit& init,
                         const Vec3<float>& origin = Vec3<float>::zero());

}  // namespace romp::analysis
