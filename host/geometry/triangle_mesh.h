// TriangleMesh: an indexed triangle surface, its bounds and enclosed volume, and placing it in a scene.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "host/geometry/bounds.h"
#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"

namespace romp::geometry {

struct TriangleMesh {
  std::vector<Vec3<double>> vertices;
  // Vertex indices, counter-clockwise seen from outside (so normals face outward).
  std::vector<std::array<std::int32_t, 3>> triangles;
  std::string name;  // where it came from (the file for loaded meshes), for messages

  Bounds bounds() const;
  // Σ over triangles of a · (b × c) / 6 (divergence theorem): the enclosed volume of a closed mesh,
  // positive when the normals face outward.
  double signed_volume() const;
};

// Each vertex x becomes rotation · (scale ⊙ x) + translation.
TriangleMesh transformed(const TriangleMesh& mesh, const Vec3<double>& scale, const Mat3<double>& rotation,
                         const Vec3<double>& translation);

// Places a mesh in a scene: scales it uniformly so the largest side of its bounding box is
// `largest_side`, rotates it about its bounding-box centre, then moves that centre to `center`.
TriangleMesh fit_to(const TriangleMesh& mesh, double largest_side, const Vec3<double>& center,
                    const Mat3<double>& rotation = Mat3<double>::identity());

}  // namespace romp::geometry
