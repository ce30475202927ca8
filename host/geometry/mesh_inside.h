// MeshInsideTest: which points a closed triangle mesh encloses, by the winding number along a +z ray.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "host/geometry/bounds.h"
#include "host/geometry/triangle_mesh.h"

namespace romp::geometry {

// The ray from p towards +z is tested against the triangles whose xy-projections share p's cell of
// a 2-D bucket grid. Whether the projection of p lies in a projected triangle is decided with
// exact-sign orientations (orient2d) and a symbolic perturbation of p by (ε, ε²), so a point whose
// ray runs exactly through an edge or a vertex is counted in exactly one of the triangles there: for a
// closed mesh the count is exact however the points line up with the vertices, and one ray is
// enough (no vote over several rays). Only a point within rounding distance of the surface may be
// classified either way; a point exactly on a face normal to z counts as inside on the face whose
// normal points −z and outside on the one pointing +z, like a half-open interval.
//
// Speed, measured in a Release build on one core of the development machine (an Intel Xeon): the
// 1.0e6 points of a lattice filling the bounds of the 69,664-triangle bunny in 0.12 s (116 ns per
// point; building the grid 0.016 s), of the 5,856-triangle spot in 0.13 s.
class MeshInsideTest {
 public:
  explicit MeshInsideTest(const TriangleMesh& mesh);

  // Σ over the triangles the ray crosses above p of +1 where it leaves through a triangle facing +z
  // and −1 where it enters through one facing −z: 1 inside a closed outward-facing mesh, 0 outside
  // (more where closed shells overlap).
  int winding_number(const Vec3<double>& p) const;
  bool contains(const Vec3<double>& p) const { return winding_number(p) != 0; }

 private:
  struct Triangle {
    Vec3<double> a, b, c;
    double z_max;
  };

  std::size_t cell_of(const Vec3<double>& p) const;
  int column(double value, int axis) const;

  Bounds bounds_;
  int cells_[2] = {1, 1};
  double inverse_cell_size_[2] = {0.0, 0.0};
  std::vector<Triangle> triangles_;            // those whose xy-projection has non-zero area
  std::vector<std::size_t> cell_begin_;        // triangles of cell i: cell_triangles_[cell_begin_[i], cell_begin_[i+1])
  std::vector<std::uint32_t> cell_triangles_;  // indices into triangles_
};

}  // namespace romp::geometry
