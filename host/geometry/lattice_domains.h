// Hexahedral particle domains for lattice-sampled bodies: each particle's lattice cell, corners shared.
#pragma once

#include "host/geometry/sampling.h"
#include "kernels/mpm/particle_set.h"

namespace romp::geometry {

// Gives the particles [first, first + body.points.size()) of `init`, sampled with
// SamplingMethod::Lattice at `spacing`, the lattice cells they are the centres of as domains. The
// body's neighbouring particles share the corners between their cells (corners of different calls
// are never shared: bodies stay separate). Weights come from hex_domain_weights. Particles appended
// before without a domain get kNoDomain. Throws romp::Error when a point is not a lattice centre.
void append_lattice_domains(mpm::ParticleInit& init, Index first, const SampledBody& body, double spacing);

// The particles of the axis-aligned box [low, high] (as sample_box, which `spec` must ask for a
// lattice), each with its lattice cell as a domain.
mpm::ParticleInit sample_box_with_domains(const Vec3<float>& low, const Vec3<float>& high, const SamplingSpec& spec,
                                          double density);

// Every corner of the domain of a particle in a Dirichlet group follows that group (where particles
// of several groups share a corner, the lowest group wins), so the domains glue the free material to
// the prescribed motion.
void assign_corner_dirichlet_groups(mpm::ParticleInit& init);

}  // namespace romp::geometry
