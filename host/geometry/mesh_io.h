// Reading triangle meshes from Wavefront OBJ and PLY files.
#pragma once

#include <string>

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

}  // namespace romp::geometry
