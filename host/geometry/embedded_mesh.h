// Points and surface meshes embedded in particle domains: each point rides in one domain at fixed
// trilinear coordinates, so it follows the deformed corners (the enriched-MPM paper, Sec. 4.1).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "host/geometry/triangle_mesh.h"
#include "kernels/mpm/domain_init.h"

namespace romp::geometry {

struct EmbeddedPoints {
  std::vector<std::int32_t> domain;     // per point; -1 for a point that no domain holds
  std::vector<Vec3<double>> reference;  // per point: ξ in the domain's cell [−1, 1]³ (outside for points
                                        // beyond the sampled cells: extrapolated)

  // Σ_α N_α(ξ) y_α over each embedded point's domain corners, y holding 3 planes over `domains`'
  // corners (their positions, or velocities); zero for a point that no domain holds.
  std::vector<Vec3<double>> interpolate(const mpm::DomainInit& domains, const std::vector<float>& corner_values) const;
};

// Embeds `points` in the lattice-cell domains [first_domain, domains.count()) of `domains` (one body's,
// from append_lattice_domains at `spacing`): each in the domain of the cell that contains it, or,
// where that cell holds no particle, of the nearest one that does within two cells; -1 beyond.
EmbeddedPoints embed_points(const std::vector<Vec3<double>>& points, const mpm::DomainInit& domains, Index first_domain,
                            double spacing);

struct EmbeddedMesh {
  std::string name;  // the object's
  std::vector<std::array<std::int32_t, 3>> triangles;
  EmbeddedPoints vertices;

  // The vertices where the domains' corners are: corner_x holds 3 planes over `domains`' corners.
  std::vector<Vec3<double>> deformed(const mpm::DomainInit& domains, const std::vector<float>& corner_x) const {
    return vertices.interpolate(domains, corner_x);
  }
};

// embed_points for a mesh's vertices. Throws romp::Error naming the mesh when a vertex is more than two
// cells from every sampled cell.
EmbeddedMesh embed_mesh(const TriangleMesh& mesh, const std::string& name, const mpm::DomainInit& domains,
                        Index first_domain, double spacing);

}  // namespace romp::geometry
