// Test meshes (cube, octahedron, icosphere), their OBJ/PLY text, and scratch folders.
#include "tests/host/geometry/test_meshes.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace romp::geometry::test {
namespace {

// Makes every face of a mesh that is star-shaped about `center` face away from it.
void orient_outward(TriangleMesh& mesh, const Vec3<double>& center) {
  for (auto& t : mesh.triangles) {
    const Vec3<double>& a = mesh.vertices[t[0]];
    const Vec3<double> normal = cross(mesh.vertices[t[1]] - a, mesh.vertices[t[2]] - a);
    if (dot(normal, a - center) < 0.0) std::swap(t[1], t[2]);
  }
}

}  // namespace

TriangleMesh cube_mesh(double low, double high) {
  TriangleMesh mesh;
  mesh.name = "cube";
  for (int k = 0; k < 8; ++k) mesh.vertices.emplace_back(k & 1 ? high : low, k & 2 ? high : low, k & 4 ? high : low);
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = 1 << ((axis + 1) % 3), v = 1 << ((axis + 2) % 3), base = side << axis;
      const std::int32_t quad[4] = {base, base + u, base + u + v, base + v};
      mesh.triangles.push_back({quad[0], quad[1], quad[2]});
      mesh.triangles.push_back({quad[0], quad[2], quad[3]});
    }
  orient_outward(mesh, Vec3<double>::constant(0.5 * (low + high)));
  return mesh;
}

TriangleMesh octahedron_mesh() {
  TriangleMesh mesh;
  mesh.name = "octahedron";
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {1.0, -1.0}) mesh.vertices.push_back(sign * Vec3<double>::unit(axis));
  for (int s = 0; s < 8; ++s) mesh.triangles.push_back({s & 1, 2 + ((s >> 1) & 1), 4 + ((s >> 2) & 1)});
  orient_outward(mesh, Vec3<double>::zero());
  return mesh;
}

TriangleMesh icosphere_mesh(int levels) {
  TriangleMesh mesh;
  mesh.name = "icosphere";
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  const double corners[12][3] = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                                 {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (const auto& c : corners) {
    const Vec3<double> p(c[0], c[1], c[2]);
    mesh.vertices.push_back(p * (1.0 / norm(p)));
  }
  mesh.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                    {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> midpoints;
    const auto midpoint = [&](std::int32_t i, std::int32_t j) {
      const auto key = std::minmax(i, j);
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      const Vec3<double> m = mesh.vertices[i] + mesh.vertices[j];
      mesh.vertices.push_back(m * (1.0 / norm(m)));
      return midpoints[key] = std::int32_t(mesh.vertices.size() - 1);
    };
    std::vector<std::array<std::int32_t, 3>> finer;
    for (const auto& f : mesh.triangles) {
      const std::int32_t ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      finer.insert(finer.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
    }
    mesh.triangles = std::move(finer);
  }
  orient_outward(mesh, Vec3<double>::zero());
  return mesh;
}

std::string to_obj(const TriangleMesh& mesh) {
  std::string text = "# " + mesh.name + "\n";
  for (const auto& v : mesh.vertices) text += fmt::format("v {} {} {}\n", v[0], v[1], v[2]);
  for (const auto& t : mesh.triangles) text += fmt::format("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
  return text;
}

std::string to_ascii_ply(const TriangleMesh& mesh) {
  std::string text = fmt::format(
      "ply\nformat ascii 1.0\ncomment {}\nelement vertex {}\nproperty double x\nproperty double y\n"
      "property double z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
      mesh.name, mesh.vertices.size(), mesh.triangles.size());
  for (const auto& v : mesh.vertices) text += fmt::format("{} {} {}\n", v[0], v[1], v[2]);
  for (const auto& t : mesh.triangles) text += fmt::format("3 {} {} {}\n", t[0], t[1], t[2]);
  return text;
}

std::string to_binary_ply(const TriangleMesh& mesh) {
  std::string bytes = fmt::format(
      "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty double x\nproperty double y\n"
      "property double z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
      mesh.vertices.size(), mesh.triangles.size());
  const auto put = [&bytes](const auto& value) {
    char raw[sizeof value];
    std::memcpy(raw, &value, sizeof value);  // the test machines are little-endian, as the format
    bytes.append(raw, sizeof value);
  };
  for (const auto& v : mesh.vertices)
    for (int a = 0; a < 3; ++a) put(v[a]);
  for (const auto& t : mesh.triangles) {
    put(std::uint8_t(3));
    for (std::int32_t index : t) put(index);
  }
  return bytes;
}

}  // namespace romp::geometry::test
