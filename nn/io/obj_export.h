// Wavefront OBJ surfaces for viewers: the embedded meshes of particle domains, one file per frame.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/math/vec3.h"

namespace romp::io {

// Writes the triangle mesh to `path` atomically (1-based indices, as OBJ counts).
void write_obj(const std::string& path, const std::vector<Vec3<double>>& vertices,
               const std::vector<std::array<std::int32_t, 3>>& triangles, const std::string& comment);

// "<folder>/<stem>_meshes/<name>_000012.obj" for "<folder>/<stem>.h5".
std::string mesh_frame_path(const std::string& snapshot_path, const std::string& name, std::int64_t frame);

}  // namespace romp::io
