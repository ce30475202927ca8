// Surface meshes embedded in particle domains: each vertex rides in one domain at fixed trilinear
// coordinates, so the mesh follows the deformed corners (the enriched-MPM paper, Sec. 4.1).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "host/geometry/triangle_mesh.h"
#include "kernels/mpm/domain_init.h"

namespace romp::geometry {

struct EmbeddedMesh {
  std::string name;                                  // the object's
  std::vector<std::array<std::int32_t, 3>> triangles;
  std::vector<std::int32_t> domain;                  // per vertex
  std::vector<Vec3<double>> reference;               // per vertex: ξ in the domain's cell [−1, 1]³ (outside for
                                                     // vertices beyond the sampled cells: extrapolated)

  // The vertices where the domains' corners are: corner_x holds 3 planes over `domains`' corners.
  std::vector<Vec3<double>> deformed(const mpm::DomainInit& domains, const std::vector<float>& corner_x) const;
};

// Embeds `mesh` in the lattice-cell domains [first_domain, domains.count()) of `domains` (one body's,
// from append_lattice_domains at `spacing`): each vertex in the domain of the cell that contains it,
// or, where that cell holds no particle, of the nearest one that does within two cells. Throws
// romp::Error naming the mesh when a vertex has none that close.
EmbeddedMesh embed_mesh(const TriangleMesh& mesh, const std::string& name, const mpm::DomainInit& domains,
                        Index first_domain, double spacing);

}  // namespace romp::geometry
