// Small closed meshes with known insides, writers of OBJ and PLY files, and a scratch folder, for the geometry tests.
#pragma once

#include <filesystem>
#include <string>

#include "host/geometry/triangle_mesh.h"
#include "tests/support/scratch_folder.h"

namespace romp::geometry::test {

// [low, high]³ as 12 outward-facing triangles (each face split along a diagonal).
TriangleMesh cube_mesh(double low, double high);
// |x| + |y| + |z| <= 1: 6 vertices on the axes, 8 faces.
TriangleMesh octahedron_mesh();
// The unit sphere approximated by an icosahedron subdivided `levels` times (20·4^levels faces).
TriangleMesh icosphere_mesh(int levels);

std::string to_obj(const TriangleMesh& mesh);
std::string to_ascii_ply(const TriangleMesh& mesh);
// Coordinates as float64 (so the mesh reads back exactly), indices as `list uchar int vertex_indices`.
std::string to_binary_ply(const TriangleMesh& mesh);

using romp::test::error_message;
using romp::test::ScratchFolder;

}  // namespace romp::geometry::test
