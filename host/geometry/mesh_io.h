// Reading triangle meshes from Wavefront OBJ and PLY files, and point clouds from PLY files.
#pragma once

#include <string>
#include <vector>

#include "host/geometry/triangle_mesh.h"

namespace romp::geometry {

// Reads `path` as OBJ or PLY by its extension (.obj, .ply, any case); the mesh is named `path`.
// Polygons are fan-triangulated. Every problem throws romp::Error naming the file and the line
// (OBJ, ascii PLY) or the element and item (binary PLY): a missing file, an unknown extension, a bad
// number, an index out of range, no faces, an unsupported PLY format or a truncated file.
TriangleMesh load_mesh(const std::string& path);

// OBJ text: `v x y z` and `f` records whose vertex references may be `i`, `i/t`, `i/t/n` or `i//n`,
// 1-based or negative (relative to the last vertex so far). Other records are ignored.
TriangleMesh parse_obj(const std::string& text, const std::string& name);

// PLY contents, ascii or binary_little_endian: the x, y, z properties of `vertex` (any numeric type,
// other properties skipped) and the `vertex_indices` (or `vertex_index`) list of `face` (any integer
// types); other elements are skipped.
TriangleMesh parse_ply(const std::string& bytes, const std::string& name);

// Points with, where the file has them, a velocity and a volume each.
struct PointCloud {
  std::vector<Vec3<double>> x;
  std::vector<Vec3<double>> v;  // empty, or one per point
  std::vector<double> volume;   // empty, or one per point
};

// PLY contents as points: the vertex element's x, y, z and, when present, vx, vy, vz and volume (any
// numeric types; other properties and elements are skipped). Errors as parse_ply's.
PointCloud parse_ply_points(const std::string& bytes, const std::string& name);

}  // namespace romp::geometry
