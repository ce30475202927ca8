// PLY point clouds for viewers without HDF5 (Blender, Houdini): one binary little-endian file per frame.
#pragma once

#include <cstdint>
#include <string>

#include "kernels/core/span.h"

namespace romp::io {

// One frame's points in engine layout (planes, initial order). The vertex element has
// float x, y, z; then float vx, vy, vz when `v` is given; then int material when `material` is given.
struct PlyPoints {
  Span<const float> x;                // 3 planes of n
  Span<const float> v;                // 3 planes of n, or empty
  Span<const std::int32_t> material;  // n ids, or empty
};

// Writes `points` to `path` atomically; `comment` (one line) goes into the header.
void write_ply(const std::string& path, const PlyPoints& points, const std::string& comment);

}  // namespace romp::io
