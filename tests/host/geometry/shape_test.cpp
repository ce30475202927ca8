// Primitives and Shape: inside tests, bounds and volumes against analytic answers, and validation errors.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "host/geometry/shape.h"
#include "kernels/math/rotation.h"
#include "tests/host/geometry/test_meshes.h"

namespace romp::geometry {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool mentions(const std::string& message, const std::string& part) { return message.find(part) != std::string::npos; }

// Every point of `shape` found by sampling its bounds densely lies inside those bounds, and the
// bounds are tight: points inside come within `slack` of each face.
void expect_tight_bounds(const Shape& shape, double slack) {
  const Bounds bounds = shape.bounds();
  Bounds seen{Vec3<double>::constant(1e300), Vec3<double>::constant(-1e300)};
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int n = 0; n < 200000; ++n) {
    Vec3<double> p;
    for (int a = 0; a < 3; ++a) p[a] = bounds.low[a] + unit(random) * (bounds.high[a] - bounds.low[a]);
    if (!shape.contains(p)) continue;
    for (int a = 0; a < 3; ++a) {
      seen.low[a] = std::min(seen.low[a], p[a]);
      seen.high[a] = std::max(seen.high[a], p[a]);
    }
  }
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(seen.low[a], bounds.low[a], slack) << shape.describe() << " axis " << a;
    EXPECT_NEAR(seen.high[a], bounds.high[a], slack) << shape.describe() << " axis " << a;
  }
}

TEST(Primitives, RotatedBoxContainsItsRotatedCorners) {
  Box box;
  box.center = Vec3<double>(1.0, 2.0, 3.0);
  box.half_extents = Vec3<double>(0.5, 0.25, 0.125);
  box.rotation = rotation_from_vector(Vec3<double>(0.0, 0.0, kPi / 2.0));  // local x → world y
  EXPECT_TRUE(box.contains(box.center + Vec3<double>(0.0, 0.49, 0.0)));
  EXPECT_FALSE(box.contains(box.center + Vec3<double>(0.49, 0.0, 0.0)));
  EXPECT_TRUE(box.contains(box.center + Vec3<double>(-0.24, -0.49, 0.12)));
  EXPECT_FALSE(box.contains(box.center + Vec3<double>(-0.24, -0.49, 0.13)));
  EXPECT_DOUBLE_EQ(box.analytic_volume(), 1.0 * 0.5 * 0.25);
  const Bounds bounds = box.bounds();
  EXPECT_NEAR(bounds.low[0], 0.75, 1e-12);
  EXPECT_NEAR(bounds.high[1], 2.5, 1e-12);
}

TEST(Primitives, TiltedCylinderContainsPointsNearItsAxisAndCaps) {
  Cylinder cylinder;
  cylinder.center = Vec3<double>(0.0, 0.0, 1.0);
  cylinder.axis = Vec3<double>(1.0, 0.0, 1.0) * (1.0 / std::sqrt(2.0));
  cylinder.radius = 0.2;
  cylinder.half_height = 0.5;
  EXPECT_TRUE(cylinder.contains(cylinder.center + 0.49 * cylinder.axis));
  EXPECT_FALSE(cylinder.contains(cylinder.center + 0.51 * cylinder.axis));
  EXPECT_TRUE(cylinder.contains(cylinder.center + Vec3<double>(0.0, 0.19, 0.0)));
  EXPECT_FALSE(cylinder.contains(cylinder.center + Vec3<double>(0.0, 0.21, 0.0)));
  EXPECT_DOUBLE_EQ(cylinder.analytic_volume(), kPi * 0.04 * 1.0);
}

TEST(Primitives, CapsuleIsTheSegmentsNeighbourhood) {
  Capsule capsule;
  capsule.a = Vec3<double>(0.0, 0.0, 0.0);
  capsule.b = Vec3<double>(1.0, 0.0, 0.0);
  capsule.radius = 0.25;
  EXPECT_TRUE(capsule.contains(Vec3<double>(-0.24, 0.0, 0.0)));
  EXPECT_FALSE(capsule.contains(Vec3<double>(-0.26, 0.0, 0.0)));
  EXPECT_TRUE(capsule.contains(Vec3<double>(0.5, 0.0, 0.24)));
  EXPECT_FALSE(capsule.contains(Vec3<double>(1.1, 0.2, 0.2)));
  EXPECT_DOUBLE_EQ(capsule.analytic_volume(), kPi * 0.0625 * (1.0 + 4.0 / 3.0 * 0.25));
  Capsule ball = capsule;
  ball.b = ball.a;  // a degenerate segment is a sphere
  EXPECT_DOUBLE_EQ(ball.analytic_volume(), (Sphere{ball.a, 0.25}.analytic_volume()));
}

TEST(Primitives, BoundsAreTightForEveryPrimitive) {
  Box box;
  box.center = Vec3<double>(0.1, -0.2, 0.3);
  box.half_extents = Vec3<double>(0.3, 0.2, 0.1);
  box.rotation = rotation_from_vector(Vec3<double>(0.3, -0.5, 0.7));
  Cylinder cylinder;
  cylinder.axis = Vec3<double>(0.2, 0.5, 0.8) * (1.0 / std::sqrt(0.93));
  cylinder.radius = 0.2;
  cylinder.half_height = 0.4;
  const Capsule capsule{Vec3<double>(0.0, 0.1, 0.2), Vec3<double>(0.5, -0.3, 0.4), 0.15};
  const Sphere sphere{Vec3<double>(1.0, 1.0, 1.0), 0.3};
  for (const Shape& shape : {Shape(box), Shape(cylinder), Shape(capsule), Shape(sphere)})
    expect_tight_bounds(shape, 0.03);
}

TEST(ShapeValidation, RejectsNonPositiveSizesNamingTheParameter) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(mentions(test::error_message([] { Shape(Sphere{Vec3<double>::zero(), 0.0}); }), "radius"));
  EXPECT_TRUE(mentions(test::error_message([] { Shape(Sphere{Vec3<double>::zero(), -1.0}); }), "radius"));
  EXPECT_TRUE(mentions(test::error_message([&] { Shape(Sphere{Vec3<double>::zero(), nan}); }), "radius"));
  Box box;
  box.half_extents = Vec3<double>(1.0, 0.0, 1.0);
  EXPECT_TRUE(mentions(test::error_message([&] { Shape{box}; }), "half extent y"));
  Cylinder cylinder;
  cylinder.radius = 1.0;
  EXPECT_TRUE(mentions(test::error_message([&] { Shape{cylinder}; }), "half height"));
  EXPECT_TRUE(mentions(test::error_message([] {
                         Shape(Capsule{Vec3<double>::zero(), Vec3<double>::zero(), 0.0});
                       }),
                       "capsule"));
}

TEST(ShapeValidation, RejectsAZeroOrNonUnitCylinderAxis) {
  Cylinder cylinder;
  cylinder.radius = 1.0;
  cylinder.half_height = 1.0;
  cylinder.axis = Vec3<double>::zero();
  EXPECT_TRUE(mentions(test::error_message([&] { Shape{cylinder}; }), "axis must be a unit vector"));
  cylinder.axis = Vec3<double>(0.0, 2.0, 0.0);
  EXPECT_TRUE(mentions(test::error_message([&] { Shape{cylinder}; }), "axis must be a unit vector"));
  cylinder.axis = Vec3<double>(0.0, 1.0, 0.0);
  EXPECT_EQ(test::error_message([&] { Shape{cylinder}; }), "(no error)");
}

TEST(ShapeValidation, RejectsARotationThatIsNotOrthonormal) {
  Box box;
  box.half_extents = Vec3<double>::constant(1.0);
  box.rotation = 1.01 * Mat3<double>::identity();
  EXPECT_TRUE(mentions(test::error_message([&] { Shape{box}; }), "not a rotation matrix"));
  box.rotation = Mat3<double>::diag(1.0, 1.0, -1.0);  // orthonormal but a reflection
  EXPECT_TRUE(mentions(test::error_message([&] { Shape{box}; }), "not a rotation matrix"));
  box.rotation = Mat3<double>(1.0, 0.1, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);  // a shear
  EXPECT_TRUE(mentions(test::error_message([&] { Shape{box}; }), "not a rotation matrix"));
  box.rotation = rotation_from_vector(Vec3<double>(1.0, 2.0, 3.0));
  EXPECT_EQ(test::error_message([&] { Shape{box}; }), "(no error)");
}

TEST(MeshSolid, VolumeIsTheDivergenceTheoremVolume) {
  const MeshSolid cube(test::cube_mesh(-0.5, 1.5));
  EXPECT_NEAR(cube.analytic_volume(), 8.0, 1e-12);
  EXPECT_NEAR(MeshSolid(test::octahedron_mesh()).analytic_volume(), 4.0 / 3.0, 1e-12);
  // Far from the origin the volume keeps its digits.
  const TriangleMesh far = transformed(test::cube_mesh(0.0, 1.0), Vec3<double>::constant(1.0), Mat3<double>::identity(),
                                       Vec3<double>::constant(1e6));
  EXPECT_NEAR(far.signed_volume(), 1.0, 1e-9);
}

TEST(MeshSolid, RejectsInwardNormalsSuggestingTheWindingIsFlipped) {
  TriangleMesh flipped = test::cube_mesh(0.0, 1.0);
  for (auto& t : flipped.triangles) std::swap(t[1], t[2]);
  const std::string message = test::error_message([&] { MeshSolid{flipped}; });
  EXPECT_TRUE(mentions(message, "cube")) << message;
  EXPECT_TRUE(mentions(message, "flip the winding")) << message;
}

TEST(MeshSolid, RejectsOpenAndInconsistentlyWoundMeshes) {
  TriangleMesh open = test::cube_mesh(0.0, 1.0);
  open.triangles.pop_back();
  EXPECT_TRUE(mentions(test::error_message([&] { MeshSolid{open}; }), "not closed"))
      << test::error_message([&] { MeshSolid{open}; });
  TriangleMesh one_flipped = test::cube_mesh(0.0, 1.0);
  std::swap(one_flipped.triangles[3][1], one_flipped.triangles[3][2]);
  EXPECT_TRUE(mentions(test::error_message([&] { MeshSolid{one_flipped}; }), "used twice in the same direction"));
  TriangleMesh bad_index = test::cube_mesh(0.0, 1.0);
  bad_index.triangles[0][2] = 8;
  EXPECT_TRUE(mentions(test::error_message([&] { MeshSolid{bad_index}; }), "outside [0, 8)"));
}

TEST(MeshSolid, AcceptsDuplicatedVerticesAsLongAsTheSurfaceIsClosed) {
  // Every triangle with vertices of its own, as STL-derived files store them.
  const TriangleMesh shared = test::octahedron_mesh();
  TriangleMesh unwelded;
  unwelded.name = "unwelded octahedron";
  for (const auto& t : shared.triangles) {
    const std::int32_t first = std::int32_t(unwelded.vertices.size());
    for (std::int32_t v : t) unwelded.vertices.push_back(shared.vertices[v]);
    unwelded.triangles.push_back({first, first + 1, first + 2});
  }
  const MeshSolid solid(unwelded);
  EXPECT_TRUE(solid.contains(Vec3<double>(0.2, 0.3, 0.1)));
  EXPECT_FALSE(solid.contains(Vec3<double>(0.5, 0.3, 0.3)));
}

TEST(TriangleMesh, FitToScalesTheLargestSideAndCentresTheBox) {
  TriangleMesh mesh = test::cube_mesh(0.0, 1.0);
  mesh = transformed(mesh, Vec3<double>(2.0, 1.0, 0.5), Mat3<double>::identity(), Vec3<double>(5.0, 5.0, 5.0));
  const Bounds before = mesh.bounds();
  EXPECT_EQ(before.low, Vec3<double>(5.0, 5.0, 5.0));
  EXPECT_EQ(before.high, Vec3<double>(7.0, 6.0, 5.5));
  const Vec3<double> center(-1.0, 0.5, 2.0);
  const Bounds fitted = fit_to(mesh, 0.5, center).bounds();
  EXPECT_NEAR(fitted.size()[0], 0.5, 1e-12);
  EXPECT_NEAR(fitted.size()[1], 0.25, 1e-12);
  EXPECT_NEAR(fitted.size()[2], 0.125, 1e-12);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(fitted.center()[a], center[a], 1e-12);
  // A quarter turn about z swaps the x and y extents, about the same centre.
  const Bounds turned = fit_to(mesh, 0.5, center, rotation_from_vector(Vec3<double>(0.0, 0.0, kPi / 2.0))).bounds();
  EXPECT_NEAR(turned.size()[0], 0.25, 1e-12);
  EXPECT_NEAR(turned.size()[1], 0.5, 1e-12);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(turned.center()[a], center[a], 1e-12);
  EXPECT_TRUE(mentions(test::error_message([&] { fit_to(mesh, 0.0, center); }), "target size"));
}

}  // namespace
}  // namespace romp::geometry
