// Small closed meshes with known insides, writers of OBJ and PLY files, and a scratch folder, for the geometry tests.
#pragma once

#include <filesystem>
#include <string>

#include "host/geometry/triangle_mesh.h"

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

// A fresh folder under the system's temporary directory, removed with everything in it on destruction.
class ScratchFolder {
 public:
  ScratchFolder();
  ~ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;

  // Writes `contents` to `name` in the folder and returns its path.
  std::string write(const std::string& name, const std::string& contents) const;
  std::string path(const std::string& name) const { return (folder_ / name).string(); }

 private:
  std::filesystem::path folder_;
};

// The message of the romp::Error that `action` throws, or "" when it throws none.
template <class Action>
std::string error_message(Action&& action) {
  try {
    action();
  } catch (const std::exception& error) {
    return error.what();
  }
  return "";
}

}  // namespace romp::geometry::test
