// Meshes embedded in lattice domains: exact at rest, carried along by any affine motion of the
// corners (trilinear interpolation reproduces affine maps), and refused when far from the body.
#include "host/geometry/embedded_mesh.h"

#include <gtest/gtest.h>

#include "host/geometry/lattice_domains.h"
#include "kernels/core/error.h"
#include "tests/host/geometry/test_meshes.h"

namespace romp::geometry {
namespace {

constexpr double kDx = 0.1;
constexpr int kPerCell = 2;

mpm::ParticleInit cube_body() {
  return sample_box_with_domains(Vec3<float>(0.2f, 0.2f, 0.2f), Vec3<float>(0.6f, 0.6f, 0.6f),
                                 SamplingSpec{SamplingMethod::Lattice, kPerCell, kDx}, 1000.0);
}

TEST(EmbeddedMesh, FollowsAnAffineMotionOfTheCornersExactly) {
  const mpm::ParticleInit init = cube_body();
  // A sphere inside the cube and its surface cube: vertices inside cells and on the body's faces.
  for (const TriangleMesh& mesh : {test::icosphere_mesh(2), test::cube_mesh(0.2, 0.6)}) {
    TriangleMesh placed = mesh;
    if (mesh.vertices.size() != 8)
      for (Vec3<double>& v : placed.vertices) v = Vec3<double>(0.4, 0.4, 0.4) + 0.15 * v;
    const EmbeddedMesh embedded = embed_mesh(placed, "surface", init.domains, 0, kDx / kPerCell);
    const std::vector<Vec3<double>> at_rest = embedded.deformed(init.domains, init.domains.corner_x);
    ASSERT_EQ(at_rest.size(), placed.vertices.size());
    for (std::size_t v = 0; v < at_rest.size(); ++v) EXPECT_LT(norm(at_rest[v] - placed.vertices[v]), 1e-6) << v;

    const Mat3<double> A(1.2, 0.1, 0.0, -0.2, 0.9, 0.3, 0.0, 0.1, 1.1);
    const Vec3<double> b(0.05, -0.02, 0.01);
    std::vector<float> moved = init.domains.corner_x;
    const Index n = init.domains.corner_count();
    for (Index c = 0; c < n; ++c) {
      const Vec3<double> x(moved[c], moved[n + c], moved[2 * n + c]);
      const Vec3<double> y = A * x + b;
      for (int a = 0; a < 3; ++a) moved[std::size_t(a * n + c)] = float(y[a]);
    }
    const std::vector<Vec3<double>> carried = embedded.deformed(init.domains, moved);
    for (std::size_t v = 0; v < carried.size(); ++v)
      EXPECT_LT(norm(carried[v] - (A * placed.vertices[v] + b)), 1e-6) << v;
  }
}

TEST(EmbeddedMesh, RefusesAMeshFarFromTheBody) {
  TriangleMesh far = test::cube_mesh(0.9, 1.0);
  try {
    embed_mesh(far, "stray", cube_body().domains, 0, kDx / kPerCell);
    FAIL() << "a mesh far outside the body was embedded";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("stray: vertex"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace romp::geometry
