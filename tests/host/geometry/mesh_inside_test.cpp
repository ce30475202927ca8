// The mesh inside test against analytic answers, including points whose rays run exactly through edges
// and vertices, and against a brute-force solid-angle winding number on a real mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "host/geometry/mesh_inside.h"
#include "host/geometry/mesh_io.h"
#include "host/geometry/mesh_solid.h"
#include "host/geometry/orientation.h"
#include "kernels/math/rotation.h"
#include "tests/host/geometry/test_meshes.h"

namespace romp::geometry {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The mesh as read back from an OBJ, an ascii PLY and a binary PLY file.
std::vector<MeshSolid> solids_from_files(const TriangleMesh& mesh, const test::ScratchFolder& folder) {
  return {MeshSolid(load_mesh(folder.write("mesh.obj", test::to_obj(mesh)))),
          MeshSolid(load_mesh(folder.write("mesh_ascii.ply", test::to_ascii_ply(mesh)))),
          MeshSolid(load_mesh(folder.write("mesh_binary.ply", test::to_binary_ply(mesh))))};
}

// Σ solid angles / 4π (van Oosterom & Strackee 1983): O(triangles) per point, no special cases.
double solid_angle_winding_number(const TriangleMesh& mesh, const Vec3<double>& p) {
  double sum = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec3<double> a = mesh.vertices[t[0]] - p, b = mesh.vertices[t[1]] - p, c = mesh.vertices[t[2]] - p;
    const double la = norm(a), lb = norm(b), lc = norm(c);
    sum += 2.0 * std::atan2(dot(a, cross(b, c)), la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb);
  }
  return sum / (4.0 * kPi);
}

TEST(Orient2d, SignIsExactForNearlyCollinearPoints) {
  // Integer coordinates below 2⁵⁰, whose determinant __int128 evaluates exactly, with c within a few
  // units of the line through a and b, where the plain double formula often gets the sign wrong.
  std::mt19937_64 random(11);
  int naive_wrong = 0;
  for (int n = 0; n < 20000; ++n) {
    const std::int64_t range = std::int64_t(1) << 49;
    const std::int64_t ax = std::int64_t(random() % range), ay = std::int64_t(random() % range);
    const std::int64_t dx = std::int64_t(random() % 4096) - 2048, dy = std::int64_t(random() % 4096) - 2048;
    const std::int64_t k = std::int64_t(random() % 1000000) + 1;
    const std::int64_t bx = ax + dx, by = ay + dy;
    const std::int64_t cx = ax + k * dx + std::int64_t(random() % 5) - 2,
                       cy = ay + k * dy + std::int64_t(random() % 5) - 2;
    const __int128 exact = __int128(ax - cx) * (by - cy) - __int128(ay - cy) * (bx - cx);
    const int expected = (exact > 0) - (exact < 0);
    const double value = orient2d(double(ax), double(ay), double(bx), double(by), double(cx), double(cy));
    ASSERT_EQ((value > 0) - (value < 0), expected) << n;
    const double naive =
        (double(ax) - double(cx)) * (double(by) - double(cy)) - (double(ay) - double(cy)) * (double(bx) - double(cx));
    naive_wrong += ((naive > 0) - (naive < 0)) != expected;
  }
  EXPECT_GT(naive_wrong, 100);  // the cases exercise the exact fallback
}

TEST(MeshInside, CubeIsExactOnLatticePlanesThroughItsVertices) {
  // Non-dyadic corners, points on the planes through them: rays along faces, edges and the
  // diagonals that split each face, and through the corners themselves.
  const double low = 0.1, high = 0.7;
  const double coordinates[] = {low - 0.05, low, 0.3, 0.4, high, high + 0.05};
  const test::ScratchFolder folder;
  int checked = 0;
  for (const MeshSolid& cube : solids_from_files(test::cube_mesh(low, high), folder)) {
    for (double x : coordinates)
      for (double y : coordinates)
        for (double z : coordinates) {
          const Vec3<double> p(x, y, z);
          bool within = true, on_surface = false;
          for (int a = 0; a < 3; ++a) {
            within = within && p[a] >= low && p[a] <= high;
            on_surface = on_surface || p[a] == low || p[a] == high;
          }
          if (within && on_surface) continue;  // on the surface either answer is right
          EXPECT_EQ(cube.contains(p), within) << cube.mesh().name << " at " << x << ", " << y << ", " << z;
          ++checked;
        }
  }
  EXPECT_EQ(checked, 3 * (216 - 56));
}

TEST(MeshInside, OctahedronIsExactOnLatticePlanesThroughItsVertices) {
  // |x| + |y| + |z| < 1. Every point below lies on a plane x, y or z = 0 or ±1 through vertices, or
  // sends its ray through a vertex or along an edge's projection.
  const double coordinates[] = {-1.5, -1.0, -0.5, -0.25, 0.0, 0.25, 0.5, 1.0, 1.5};
  const test::ScratchFolder folder;
  for (const MeshSolid& octahedron : solids_from_files(test::octahedron_mesh(), folder))
    for (double x : coordinates)
      for (double y : coordinates)
        for (double z : coordinates) {
          const double l1 = std::abs(x) + std::abs(y) + std::abs(z);
          if (l1 == 1.0) continue;
          EXPECT_EQ(octahedron.contains(Vec3<double>(x, y, z)), l1 < 1.0)
              << octahedron.mesh().name << " at " << x << ", " << y << ", " << z;
        }
}

TEST(MeshInside, RotatedIcosphereMatchesItsFacePlanes) {
  // A convex mesh holds exactly the points behind all its face planes. Half the points send their
  // ray through a vertex (x, y of a vertex), the rest are random.
  const TriangleMesh mesh =
      transformed(test::icosphere_mesh(2), Vec3<double>(0.3, 0.2, 0.25),
                  rotation_from_vector(Vec3<double>(0.4, -0.9, 0.3)), Vec3<double>(0.5, 0.1, -0.2));
  const test::ScratchFolder folder;
  const std::vector<MeshSolid> solids = solids_from_files(mesh, folder);
  const Bounds bounds = mesh.bounds();
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(-0.1, 1.1);
  int checked = 0;
  for (int n = 0; n < 4000; ++n) {
    Vec3<double> p;
    for (int a = 0; a < 3; ++a) p[a] = bounds.low[a] + unit(random) * (bounds.high[a] - bounds.low[a]);
    if (n % 2 == 1) {
      const Vec3<double>& vertex = mesh.vertices[random() % mesh.vertices.size()];
      p[0] = vertex[0];
      p[1] = vertex[1];
    }
    double nearest_plane = 1e300;
    bool inside = true;
    for (const auto& t : mesh.triangles) {
      const Vec3<double>& a = mesh.vertices[t[0]];
      const Vec3<double> normal = cross(mesh.vertices[t[1]] - a, mesh.vertices[t[2]] - a);
      const double distance = dot(normal, p - a) / norm(normal);
      nearest_plane = std::min(nearest_plane, std::abs(distance));
      inside = inside && distance < 0.0;
    }
    if (nearest_plane < 1e-9) continue;
    for (const MeshSolid& solid : solids) EXPECT_EQ(solid.contains(p), inside) << solid.mesh().name << " point " << n;
    ++checked;
  }
  EXPECT_GT(checked, 3900);
}

TEST(MeshInside, SpotMatchesTheSolidAngleWindingNumber) {
  // A non-convex mesh (a cow: legs, ears, horns). A third of the rays run through a vertex, a third
  // lie on the plane x = vertex x.
  const TriangleMesh spot = load_mesh(std::string(ROMP_SCENE_ASSETS_DIR) + "/spot.obj");
  const MeshSolid solid(spot);
  const Bounds bounds = solid.bounds();
  std::mt19937_64 random(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int checked = 0, inside = 0;
  for (int n = 0; n < 600; ++n) {
    Vec3<double> p;
    for (int a = 0; a < 3; ++a) p[a] = bounds.low[a] + unit(random) * (bounds.high[a] - bounds.low[a]);
    const Vec3<double>& vertex = spot.vertices[random() % spot.vertices.size()];
    if (n % 3 >= 1) p[0] = vertex[0];
    if (n % 3 == 2) p[1] = vertex[1];
    const double winding = solid_angle_winding_number(spot, p);
    if (std::abs(winding - std::round(winding)) > 0.1) continue;  // within rounding of the surface
    EXPECT_EQ(solid.contains(p), std::round(winding) != 0.0) << "point " << n << " winding " << winding;
    ++checked;
    inside += std::round(winding) != 0.0;
  }
  EXPECT_GT(checked, 590);
  EXPECT_GT(inside, 60);  // the sample is not all outside
}

TEST(MeshInside, WindingNumberCountsOverlappingShells) {
  TriangleMesh two = test::cube_mesh(0.0, 1.0);
  const TriangleMesh second = test::cube_mesh(0.5, 1.5);
  for (auto t : second.triangles) {
    for (auto& v : t) v += 8;
    two.triangles.push_back(t);
  }
  two.vertices.insert(two.vertices.end(), second.vertices.begin(), second.vertices.end());
  const MeshInsideTest inside(two);
  EXPECT_EQ(inside.winding_number(Vec3<double>(0.25, 0.25, 0.25)), 1);
  EXPECT_EQ(inside.winding_number(Vec3<double>(0.75, 0.75, 0.75)), 2);
  EXPECT_EQ(inside.winding_number(Vec3<double>(1.25, 1.25, 1.25)), 1);
  EXPECT_EQ(inside.winding_number(Vec3<double>(0.25, 1.25, 0.75)), 0);
  EXPECT_TRUE(MeshSolid(two).contains(Vec3<double>(0.75, 0.75, 0.75)));
}

}  // namespace
}  // namespace romp::geometry
