// Particle sampling: mass against analytic volumes for every shape and method, lattice alignment,
// determinism, Poisson-disk spacing and density, errors, and appending bodies to a ParticleInit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "host/geometry/mesh_io.h"
#include "host/geometry/poisson_disk.h"
#include "host/geometry/sampling.h"
#include "kernels/math/rotation.h"
#include "tests/host/geometry/test_meshes.h"

namespace romp::geometry {
namespace {

const char* name_of(SamplingMethod method) {
  switch (method) {
    case SamplingMethod::Lattice: return "Lattice";
    case SamplingMethod::JitteredLattice: return "JitteredLattice";
    case SamplingMethod::PoissonDisk: return "PoissonDisk";
  }
  return "?";
}

}  // namespace

// How GoogleTest (and so ctest's test names) print a method; found by argument-dependent lookup.
void PrintTo(SamplingMethod method, std::ostream* out) { *out << name_of(method); }

namespace {

constexpr double kDensity = 1000.0;

bool mentions(const std::string& message, const std::string& part) { return message.find(part) != std::string::npos; }

double mass_of(const SampledBody& body) { return kDensity * body.particle_volume * double(body.points.size()); }

SamplingSpec spec_of(SamplingMethod method, double dx, int per_cell = 2, std::uint64_t seed = 7) {
  SamplingSpec spec;
  spec.method = method;
  spec.dx = dx;
  spec.per_cell = per_cell;
  spec.seed = seed;
  return spec;
}

// The smallest distance between two of the points (brute force).
double minimum_distance(const std::vector<Vec3<double>>& points) {
  double smallest = 1e300;
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t j = i + 1; j < points.size(); ++j)
      smallest = std::min(smallest, squared_norm(points[i] - points[j]));
  return std::sqrt(smallest);
}

// The shapes of the mass test, each at least 20 spacings of 0.01 across its smallest dimension and
// placed off the lattice's symmetry planes. The mass is the lattice count × h³ for every method, and
// that count is coarse for small round shapes: over 40 random centres a sphere 10 spacings across
// was off by up to 3.7%, one 20 across by up to 1.1%, a tilted cylinder or capsule 20 across by
// 0.5%. An axis-aligned box is exact when its sides are whole spacings, as here, and otherwise off
// by up to a layer of particles.
std::vector<Shape> primitive_shapes() {
  Box box;
  box.center = Vec3<double>(0.013, 0.021, -0.007);
  box.half_extents = Vec3<double>(0.1, 0.15, 0.2);
  Box rotated = box;
  rotated.rotation = rotation_from_vector(Vec3<double>(0.3, 0.5, -0.4));
  const Sphere sphere{Vec3<double>(0.0031, -0.0043, 0.0017), 0.12};
  Cylinder tilted;
  tilted.center = Vec3<double>(0.004, 0.006, 0.002);
  tilted.axis = Vec3<double>(1.0, 2.0, 2.0) * (1.0 / 3.0);
  tilted.radius = 0.12;
  tilted.half_height = 0.15;
  const Capsule capsule{Vec3<double>(-0.1, 0.02, 0.03), Vec3<double>(0.12, 0.07, -0.04), 0.12};
  return {box, rotated, sphere, tilted, capsule};
}

class SampledMass : public ::testing::TestWithParam<SamplingMethod> {};

TEST_P(SampledMass, IsWithinOnePercentOfDensityTimesVolumeForEveryPrimitive) {
  for (const Shape& shape : primitive_shapes()) {
    const SampledBody body = sample(shape, spec_of(GetParam(), 0.02));
    const double expected = kDensity * shape.analytic_volume();
    EXPECT_NEAR(mass_of(body), expected, 0.01 * expected) << shape.describe();
    for (const Vec3<double>& p : body.points) ASSERT_TRUE(shape.contains(p)) << shape.describe();
  }
}

TEST_P(SampledMass, IsWithinOnePercentOfTheDivergenceVolumeForSpot) {
  const Shape spot = MeshSolid(load_mesh(std::string(ROMP_SCENE_ASSETS_DIR) + "/spot.obj"));
  // h = 0.04: 24 particles across the narrowest side of its bounds (0.94), 11,000 in all.
  const SampledBody body = sample(spot, spec_of(GetParam(), 0.08));
  const double expected = kDensity * spot.analytic_volume();
  EXPECT_NEAR(mass_of(body), expected, 0.01 * expected);
  EXPECT_GT(body.points.size(), 10000u);
}

std::string method_name(const ::testing::TestParamInfo<SamplingMethod>& info) { return name_of(info.param); }

INSTANTIATE_TEST_SUITE_P(Methods, SampledMass,
                         ::testing::Values(SamplingMethod::Lattice, SamplingMethod::JitteredLattice,
                                           SamplingMethod::PoissonDisk),
                         method_name);

TEST(Sampling, LatticePointsOfSeparateBodiesLieOnOneGlobalLattice) {
  const double h = 0.01;
  const Sphere a{Vec3<double>(0.0123, 0.0456, 0.0789), 0.05};
  Box b;
  b.center = Vec3<double>(0.2, -0.3, 0.1);
  b.half_extents = Vec3<double>(0.03, 0.04, 0.05);
  for (const Shape& shape : {Shape(a), Shape(b)}) {
    const SampledBody body = sample(shape, spec_of(SamplingMethod::Lattice, 2.0 * h));
    EXPECT_DOUBLE_EQ(body.particle_volume, h * h * h);
    for (const Vec3<double>& p : body.points)
      for (int axis = 0; axis < 3; ++axis) {
        const double index = p[axis] / h - 0.5;
        ASSERT_NEAR(index, std::round(index), 1e-9) << shape.describe();
      }
  }
  // A box whose faces lie on lattice planes holds exactly its cells' centres.
  Box aligned;
  aligned.center = Vec3<double>(0.5, 0.25, 0.0);
  aligned.half_extents = Vec3<double>(0.125, 0.0625, 0.25);
  EXPECT_EQ(sample(aligned, spec_of(SamplingMethod::Lattice, 1.0 / 32.0, 2)).points.size(), 16u * 8u * 32u);
}

TEST(Sampling, JitteredPointsStayWithinTheJitterOfTheirLatticePoint) {
  const Sphere sphere{Vec3<double>::zero(), 0.1};
  SamplingSpec spec = spec_of(SamplingMethod::JitteredLattice, 0.02);
  spec.jitter = 0.5;
  const double h = spec.spacing();
  const SampledBody body = sample(sphere, spec);
  double largest = 0.0;
  for (const Vec3<double>& p : body.points)
    for (int axis = 0; axis < 3; ++axis) {
      const double offset = p[axis] / h - 0.5;
      largest = std::max(largest, std::abs(offset - std::round(offset)));
    }
  EXPECT_LE(largest, 0.25 + 1e-9);
  EXPECT_GT(largest, 0.24);  // and they do move
}

TEST(Sampling, SameSeedGivesTheSamePointsAndAnotherSeedOthers) {
  const Capsule capsule{Vec3<double>(0.0, 0.0, 0.0), Vec3<double>(0.1, 0.05, 0.0), 0.06};
  for (SamplingMethod method : {SamplingMethod::JitteredLattice, SamplingMethod::PoissonDisk}) {
    const SampledBody first = sample(capsule, spec_of(method, 0.02, 2, 42));
    const SampledBody again = sample(capsule, spec_of(method, 0.02, 2, 42));
    const SampledBody other = sample(capsule, spec_of(method, 0.02, 2, 43));
    ASSERT_EQ(first.points.size(), again.points.size());
    EXPECT_TRUE(std::equal(first.points.begin(), first.points.end(), again.points.begin()));
    EXPECT_EQ(first.particle_volume, again.particle_volume);
    EXPECT_FALSE(first.points.size() == other.points.size() &&
                 std::equal(first.points.begin(), first.points.end(), other.points.begin()));
  }
}

TEST(Sampling, PoissonDiskKeepsTheRadiusAndTheLatticeDensity) {
  const Sphere sphere{Vec3<double>(0.01, 0.02, 0.03), 0.15};
  const SamplingSpec spec = spec_of(SamplingMethod::PoissonDisk, 0.02);
  const double h = spec.spacing();
  const SampledBody body = sample(sphere, spec);
  EXPECT_GE(minimum_distance(body.points), kPoissonRadiusPerSpacing * h);
  const double lattice_count = sphere.analytic_volume() / (h * h * h);
  EXPECT_NEAR(double(body.points.size()), lattice_count, 0.03 * lattice_count);
}

TEST(Sampling, PoissonDiskSampleOfABoxIsMaximal) {
  // No point of the box is farther than 2 r from a sample (Bridson's guarantee), checked on a lattice.
  const Bounds box{Vec3<double>::zero(), Vec3<double>(1.0, 0.5, 0.75)};
  const double radius = 0.1;
  const std::vector<Vec3<double>> points = poisson_disk_sample(box, radius, 3);
  EXPECT_GE(minimum_distance(points), radius);
  double farthest = 0.0;
  for (double x = 0.0; x <= 1.0; x += 0.05)
    for (double y = 0.0; y <= 0.5; y += 0.05)
      for (double z = 0.0; z <= 0.75; z += 0.05) {
        double nearest = 1e300;
        for (const Vec3<double>& p : points) nearest = std::min(nearest, squared_norm(p - Vec3<double>(x, y, z)));
        farthest = std::max(farthest, std::sqrt(nearest));
      }
  EXPECT_LE(farthest, 2.0 * radius);
  for (const Vec3<double>& p : points) EXPECT_TRUE(box.contains(p));
}

TEST(Sampling, AShapeSmallerThanTheSpacingIsAnErrorNamingShapeAndSpacing) {
  const Sphere speck{Vec3<double>(0.013, 0.013, 0.013), 0.001};
  for (SamplingMethod method :
       {SamplingMethod::Lattice, SamplingMethod::JitteredLattice, SamplingMethod::PoissonDisk}) {
    const std::string message = test::error_message([&] { sample(speck, spec_of(method, 0.1)); });
    EXPECT_TRUE(mentions(message, "sphere of radius 0.001")) << message;
    EXPECT_TRUE(mentions(message, "spacing h = 0.05")) << message;
  }
}

TEST(Sampling, InvalidSpecsAreErrors) {
  const Sphere sphere{Vec3<double>::zero(), 0.1};
  SamplingSpec spec = spec_of(SamplingMethod::Lattice, 0.02, 0);
  EXPECT_TRUE(mentions(test::error_message([&] { sample(sphere, spec); }), "per_cell"));
  spec = spec_of(SamplingMethod::Lattice, 0.0);
  EXPECT_TRUE(mentions(test::error_message([&] { sample(sphere, spec); }), "dx"));
  spec = spec_of(SamplingMethod::JitteredLattice, 0.02);
  spec.jitter = 1.5;
  EXPECT_TRUE(mentions(test::error_message([&] { sample(sphere, spec); }), "jitter"));
  spec = spec_of(SamplingMethod::Lattice, 1e-7);
  EXPECT_TRUE(mentions(test::error_message([&] { sample(sphere, spec); }), "lattice points"));
}

TEST(AppendBody, RebuildsComponentMajorPlanesAndKeepsEarlierParticles) {
  SampledBody first;
  first.points = {Vec3<double>(1, 2, 3), Vec3<double>(4, 5, 6)};
  first.particle_volume = 0.5;
  SampledBody second;
  second.points = {Vec3<double>(7, 8, 9), Vec3<double>(10, 11, 12), Vec3<double>(13, 14, 15)};
  second.particle_volume = 0.25;

  mpm::ParticleInit init;
  append_body(init, first, 2.0, 0);
  ASSERT_EQ(init.count(), 2);
  init.v = {1, 2, 3, 4, 5, 6};  // a velocity given to the first body: planes vx0 vx1 | vy0 vy1 | vz0 vz1
  append_body(init, second, 4.0, 3);

  ASSERT_EQ(init.count(), 5);
  EXPECT_EQ(init.x, (std::vector<float>{1, 4, 7, 10, 13, 2, 5, 8, 11, 14, 3, 6, 9, 12, 15}));
  EXPECT_EQ(init.v, (std::vector<float>{1, 2, 0, 0, 0, 3, 4, 0, 0, 0, 5, 6, 0, 0, 0}));
  EXPECT_EQ(init.mass, (std::vector<float>{1, 1, 1, 1, 1}));
  EXPECT_EQ(init.volume0, (std::vector<float>{0.5f, 0.5f, 0.25f, 0.25f, 0.25f}));
  EXPECT_EQ(init.material, (std::vector<std::int32_t>{0, 0, 3, 3, 3}));
  EXPECT_EQ(init.dirichlet_group, std::vector<std::int32_t>(5, mpm::kNoDirichletGroup));

  init.v.pop_back();
  EXPECT_TRUE(mentions(test::error_message([&] { append_body(init, second, 4.0, 0); }), "disagree"));
  EXPECT_TRUE(mentions(test::error_message([&] { append_body(init, second, 0.0, 0); }), "density"));
}

}  // namespace
}  // namespace romp::geometry
