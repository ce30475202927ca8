// Bounds, divergence-theorem volume and placement of triangle meshes.
#include "host/geometry/triangle_mesh.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "kernels/core/error.h"

namespace romp::geometry {

Bounds TriangleMesh::bounds() const {
  ROMP_CHECK(!vertices.empty(), "the bounds of mesh '" + name + "' are undefined: it has no vertices");
  Bounds box{vertices[0], vertices[0]};
  for (const Vec3<double>& v : vertices)
    for (int a = 0; a < 3; ++a) {
      box.low[a] = std::min(box.low[a], v[a]);
      box.high[a] = std::max(box.high[a], v[a]);
    }
  return box;
}

double TriangleMesh::signed_volume() const {
  // Relative to the bounding-box centre rather than the origin, so a mesh far from the origin does
  // not lose digits to cancellation between large tetrahedra.
  const Vec3<double> origin = vertices.empty() ? Vec3<double>::zero() : bounds().center();
  double six_volume = 0.0;
  for (const auto& t : triangles)
    six_volume += dot(vertices[t[0]] - origin, cross(vertices[t[1]] - origin, vertices[t[2]] - origin));
  return six_volume / 6.0;
}

TriangleMesh transformed(const TriangleMesh& mesh, const Vec3<double>& scale, const Mat3<double>& rotation,
                         const Vec3<double>& translation) {
  TriangleMesh result = mesh;
  for (Vec3<double>& v : result.vertices) v = rotation * hadamard(scale, v) + translation;
  return result;
}

TriangleMesh fit_to(const TriangleMesh& mesh, double largest_side, const Vec3<double>& center,
                    const Mat3<double>& rotation) {
  if (!(largest_side > 0.0) || !std::isfinite(largest_side))
    throw Error(fmt::format("mesh '{}': the target size must be finite and > 0, got {}", mesh.name, largest_side));
  const Bounds box = mesh.bounds();
  const Vec3<double> size = box.size();
  const double current = std::max({size[0], size[1], size[2]});
  if (!(current > 0.0))
    throw Error(fmt::format("mesh '{}' has no extent to scale: all its vertices coincide", mesh.name));
  const double s = largest_side / current;
  // x ↦ R (s (x − c₀)) + c = R (s x) + (c − R (s c₀)).
  return transformed(mesh, Vec3<double>::constant(s), rotation, center - rotation * (s * box.center()));
}

}  // namespace romp::geometry
