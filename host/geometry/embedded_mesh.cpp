// Embedding by lattice cell: a cell-to-domain map, the nearest sampled cell for stray vertices, and
// trilinear interpolation of the corners.
#include "host/geometry/embedded_mesh.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <map>

#include "kernels/core/error.h"
#include "kernels/mpm/hex_domain.h"

namespace romp::geometry {
namespace {

using Cell = std::array<std::int64_t, 3>;

}  // namespace

std::vector<Vec3<double>> EmbeddedMesh::deformed(const mpm::DomainInit& domains, const std::vector<float>& corner_x) const {
  std::vector<Vec3<double>> vertices(domain.size(), Vec3<double>::zero());
  for (std::size_t v = 0; v < domain.size(); ++v)
    for (int alpha = 0; alpha < mpm::kDomainCorners; ++alpha)
      vertices[v] += mpm::corner_shape_function(alpha, reference[v]) * domains.corner_position(corner_x, domain[v], alpha);
  return vertices;
}

EmbeddedMesh embed_mesh(const TriangleMesh& mesh, const std::string& name, const mpm::DomainInit& domains,
                        Index first_domain, double spacing) {
  // Corner 0 of a lattice domain is its cell's low corner.
  std::map<Cell, std::int32_t> domain_of_cell;
  for (Index d = first_domain; d < domains.count(); ++d) {
    const Vec3<double> low = domains.corner_position(domains.corner_x, d, 0);
    domain_of_cell[{std::llround(low[0] / spacing), std::llround(low[1] / spacing), std::llround(low[2] / spacing)}] =
        std::int32_t(d);
  }
  constexpr int kReach = 2;  // cells searched around a vertex whose own cell holds no particle
  EmbeddedMesh embedded;
  embedded.name = name;
  embedded.triangles = mesh.triangles;
  for (const Vec3<double>& vertex : mesh.vertices) {
    const Cell own{std::int64_t(std::floor(vertex[0] / spacing)), std::int64_t(std::floor(vertex[1] / spacing)),
                   std::int64_t(std::floor(vertex[2] / spacing))};
    std::int32_t best = -1;
    Cell best_cell{};
    double best_distance = std::numeric_limits<double>::infinity();
    for (int i = -kReach; i <= kReach; ++i)
      for (int j = -kReach; j <= kReach; ++j)
        for (int k = -kReach; k <= kReach; ++k) {
          const Cell cell{own[0] + i, own[1] + j, own[2] + k};
          const auto found = domain_of_cell.find(cell);
          if (found == domain_of_cell.end()) continue;
          const Vec3<double> centre((double(cell[0]) + 0.5) * spacing, (double(cell[1]) + 0.5) * spacing,
                                    (double(cell[2]) + 0.5) * spacing);
          const double distance = norm(vertex - centre);
          if (distance < best_distance) {
            best_distance = distance;
            best = found->second;
            best_cell = cell;
          }
        }
    ROMP_CHECK(best >= 0, fmt::format("{}: vertex ({}, {}, {}) is more than {} cells from every sampled cell; sample "
                                      "finer or check that the mesh is the object's",
                                      name, vertex[0], vertex[1], vertex[2], kReach));
    embedded.domain.push_back(best);
    Vec3<double> xi;
    for (int a = 0; a < 3; ++a) xi[a] = 2.0 * (vertex[a] / spacing - double(best_cell[a])) - 1.0;
    embedded.reference.push_back(xi);
  }
  return embedded;
}

}  // namespace romp::geometry
