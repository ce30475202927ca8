// Embedding by lattice cell: a cell-to-domain map, the nearest sampled cell for stray points, and
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

std::vector<Vec3<double>> EmbeddedPoints::interpolate(const mpm::DomainInit& domains,
                                                      const std::vector<float>& corner_values) const {
  std::vector<Vec3<double>> values(domain.size(), Vec3<double>::zero());
  for (std::size_t v = 0; v < domain.size(); ++v) {
    if (domain[v] < 0) continue;
    for (int alpha = 0; alpha < mpm::kDomainCorners; ++alpha)
      values[v] +=
          mpm::corner_shape_function(alpha, reference[v]) * domains.corner_position(corner_values, domain[v], alpha);
  }
  return values;
}

EmbeddedPoints embed_points(const std::vector<Vec3<double>>& points, const mpm::DomainInit& domains, Index first_domain,
                            double spacing) {
  // Corner 0 of a lattice domain is its cell's low corner.
  std::map<Cell, std::int32_t> domain_of_cell;
  for (Index d = first_domain; d < domains.count(); ++d) {
    const Vec3<double> low = domains.corner_position(domains.corner_x, d, 0);
    domain_of_cell[{std::llround(low[0] / spacing), std::llround(low[1] / spacing), std::llround(low[2] / spacing)}] =
        std::int32_t(d);
  }
  constexpr int kReach = 2;  // cells searched around a point whose own cell holds no particle
  EmbeddedPoints embedded;
  for (const Vec3<double>& point : points) {
    const Cell own{std::int64_t(std::floor(point[0] / spacing)), std::int64_t(std::floor(point[1] / spacing)),
                   std::int64_t(std::floor(point[2] / spacing))};
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
          const double distance = norm(point - centre);
          if (distance < best_distance) {
            best_distance = distance;
            best = found->second;
            best_cell = cell;
          }
        }
    embedded.domain.push_back(best);
    Vec3<double> xi = Vec3<double>::zero();
    if (best >= 0)
      for (int a = 0; a < 3; ++a) xi[a] = 2.0 * (point[a] / spacing - double(best_cell[a])) - 1.0;
    embedded.reference.push_back(xi);
  }
  return embedded;
}

EmbeddedMesh embed_mesh(const TriangleMesh& mesh, const std::string& name, const mpm::DomainInit& domains,
                        Index first_domain, double spacing) {
  EmbeddedMesh embedded;
  embedded.name = name;
  embedded.triangles = mesh.triangles;
  embedded.vertices = embed_points(mesh.vertices, domains, first_domain, spacing);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Vec3<double>& vertex = mesh.vertices[v];
    ROMP_CHECK(embedded.vertices.domain[v] >= 0,
               fmt::format("{}: vertex ({}, {}, {}) is more than two cells from every sampled cell; sample finer or "
                           "check that the mesh is the object's",
                           name, vertex[0], vertex[1], vertex[2]));
  }
  return embedded;
}

}  // namespace romp::geometry
