// Binary little-endian PLY writer: header, then one interleaved record per particle.
#include "nn/io/ply_export.h"

#include <cstring>

#include <fmt/format.h>

#include "kernels/core/error.h"
#include "nn/io/atomic_file.h"

namespace romp::io {
namespace {

// Appends the 4 bytes of a float or int32 least significant first, whatever the host's byte order.
template <class T>
void append_little_endian(std::string& bytes, T value) {
  static_assert(sizeof(T) == 4, "PLY properties here are 4-byte float or int");
  std::uint32_t bits = 0;
  std::memcpy(&bits, &value, 4);
  for (int shift = 0; shift < 32; shift += 8) bytes.push_back(char((bits >> shift) & 0xffu));
}

}  // namespace

void write_ply(const std::string& path, const PlyPoints& points, const std::string& comment) {
  const Index n = points.x.size() / 3;
  if (points.x.size() != 3 * n || (!points.v.empty() && points.v.size() != 3 * n) ||
      (!points.material.empty() && points.material.size() != n)) {
    throw Error(fmt::format("PLY {}: {} position values (3 planes), {} velocity values and {} material ids disagree",
                            path, points.x.size(), points.v.size(), points.material.size()));
  }
  if (comment.find('\n') != std::string::npos) throw Error(fmt::format("PLY {}: the comment must be one line", path));
  const bool velocity = !points.v.empty(), material = !points.material.empty();

  std::string bytes = "ply\nformat binary_little_endian 1.0\n";
  if (!comment.empty()) bytes += "comment " + comment + "\n";
  bytes += fmt::format("element vertex {}\nproperty float x\nproperty float y\nproperty float z\n", n);
  if (velocity) bytes += "property float vx\nproperty float vy\nproperty float vz\n";
  if (material) bytes += "property int material\n";
  bytes += "end_header\n";

  bytes.reserve(bytes.size() + std::size_t(n) * (12 + (velocity ? 12 : 0) + (material ? 4 : 0)));
  for (Index p = 0; p < n; ++p) {
    for (Index c = 0; c < 3; ++c) append_little_endian(bytes, points.x[c * n + p]);
    if (velocity) {
      for (Index c = 0; c < 3; ++c) append_little_endian(bytes, points.v[c * n + p]);
    }
    if (material) append_little_endian(bytes, points.material[p]);
  }
  write_file_atomically(path, bytes);
}

}  // namespace romp::io
