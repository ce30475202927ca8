// Scene setup: initial velocity fields (constants, formulas of the position, rotation about the centre
// of mass) and the affine velocity C they give APIC particles.
#include "host/scene/scene_setup.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "host/engine/full_order_sim.h"
#include "host/scene/scene_parser.h"
#include "kernels/core/error.h"
#include "nn/io/snapshot_writer.h"
#include "tests/support/scratch_folder.h"

namespace romp::scene {
namespace {

// A 0.2 m cube about (0.5, 0.5, 0.5) with `object_keys` added to its [[objects]] entry.
std::string cube_scene(const std::string& object_keys, const std::string& extra = "") {
  return R"(
[parameters]
omega = 3.0

[domain]
size = [1.0, 1.0, 1.0]
dx = 0.05

[time]
end = 0.1
frame_rate = 10

[loads]
gravity = [0, 0, 0]

[materials.jelly]
preset = "jelly"
)" + extra +
         R"(
[[objects]]
material = "jelly"
shape = { type = "box", center = [0.5, 0.5, 0.5], size = [0.2, 0.2, 0.2] }
)" + object_keys +
         "\n";
}

Vec3<double> at(const std::vector<float>& planes, Index n, Index p) {
  return Vec3<double>(planes[std::size_t(p)], planes[std::size_t(n + p)], planes[std::size_t(2 * n + p)]);
}

double C_at(const mpm::ParticleInit& init, Index p, int i, int j) {
  return init.C[std::size_t((3 * i + j) * init.count() + p)];
}

TEST(SceneSetup, AVelocityFormulaOfThePositionSetsVAndItsGradientAsC) {
  // A shear flow v = (omega (y − 0.5), 0, 0.1 z²): ∂v_x/∂y = omega, ∂v_z/∂z = 0.2 z.
  const SceneSetup setup =
      sample_scene(parse_scene(cube_scene(R"X(velocity = ["omega * (y - 0.5)", 0, "0.1 * z^2"])X"), "shear.toml"));
  const mpm::ParticleInit& init = setup.particles;
  const Index n = init.count();
  ASSERT_GT(n, 0);
  ASSERT_EQ(Index(init.C.size()), 9 * n);
  for (Index p = 0; p < n; p += 7) {
    const Vec3<double> x = at(init.x, n, p), v = at(init.v, n, p);
    EXPECT_NEAR(v[0], 3.0 * (x[1] - 0.5), 1e-6);
    EXPECT_EQ(v[1], 0.0);
    EXPECT_NEAR(v[2], 0.1 * x[2] * x[2], 1e-6);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double expected = i == 0 && j == 1 ? 3.0 : i == 2 && j == 2 ? 0.2 * x[2] : 0.0;
        EXPECT_NEAR(C_at(init, p, i, j), expected, 1e-5) << "C(" << i << ", " << j << ") of particle " << p;
      }
  }
}

TEST(SceneSetup, AngularVelocitySetsTheRotationsSkewMatrixAsC) {
  const SceneSetup setup = sample_scene(parse_scene(cube_scene("angular_velocity = [0, 0, \"omega\"]"), "spin.toml"));
  const mpm::ParticleInit& init = setup.particles;
  const Index n = init.count();
  ASSERT_EQ(Index(init.C.size()), 9 * n);
  for (Index p = 0; p < n; p += 5) {
    // ω × r for ω = (0, 0, 3): ∂v_x/∂y = −3, ∂v_y/∂x = 3.
    EXPECT_FLOAT_EQ(C_at(init, p, 0, 1), -3.0f);
    EXPECT_FLOAT_EQ(C_at(init, p, 1, 0), 3.0f);
    EXPECT_FLOAT_EQ(C_at(init, p, 0, 0), 0.0f);
    EXPECT_FLOAT_EQ(C_at(init, p, 2, 2), 0.0f);
  }
}

TEST(SceneSetup, AConstantVelocityLeavesCEmptyAndIsResolvedAsNumbers) {
  const Scene scene = parse_scene(cube_scene(R"X(velocity = ["2 * omega", 0, 0])X"), "drift.toml");
  EXPECT_EQ(scene.objects[0].velocity, Vec3<double>(6.0, 0.0, 0.0));
  EXPECT_TRUE(scene.objects[0].velocity_formulas[0].empty());
  EXPECT_TRUE(sample_scene(scene).particles.C.empty());
  EXPECT_NE(scene.resolved_text.find("velocity = [6.0, 0.0, 0.0]"), std::string::npos) << scene.resolved_text;
}

TEST(SceneSetup, AFormulaIsKeptInTheResolvedSceneAndResolvesToItself) {
  const Scene scene = parse_scene(cube_scene(R"X(velocity = ["omega * (y - 0.5)", 0, 0])X"), "shear.toml");
  EXPECT_EQ(scene.objects[0].velocity_formulas[0], "omega * (y - 0.5)");
  const Scene again = parse_scene(scene.resolved_text, "resolved.toml");
  EXPECT_EQ(again.resolved_text, scene.resolved_text);
  EXPECT_EQ(sample_scene(again).particles.v, sample_scene(scene).particles.v);
}

TEST(SceneSetup, BadVelocityFormulasAreRefusedNamingTheKeyOrTheObject) {
  const std::string unknown =
      test::error_message([] { parse_scene(cube_scene(R"X(velocity = ["omega * w", 0, 0])X"), "bad.toml"); });
  EXPECT_NE(unknown.find("bad.toml:"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("objects[0].velocity"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("unknown name 'w' (parameters: omega; variables: x, y, z)"), std::string::npos) << unknown;
  // Finite where it is parsed (no position there), infinite at some particles.
  const std::string infinite = test::error_message(
      [] { sample_scene(parse_scene(cube_scene(R"X(velocity = ["sqrt(x - 0.5)", 0, 0])X"), "pole.toml")); });
  EXPECT_NE(infinite.find("objects 'object0': velocity[0] is"), std::string::npos) << infinite;
  // Angular velocity stays a constant: a formula of the position there is refused at its key.
  const std::string spin =
      test::error_message([] { parse_scene(cube_scene(R"X(angular_velocity = [0, 0, "x"])X"), "spin.toml"); });
  EXPECT_NE(spin.find("objects[0].angular_velocity"), std::string::npos) << spin;
}

// A rigidly spinning cube, free of gravity and stress: APIC with C = ∇v carries the rotation through a
// substep exactly (an affine velocity field is what APIC transfers without loss), so every particle's
// velocity after it is still ω × (x − c), to float rounding. With C = 0 (as before) P2G
// leaves out each particle's affine momentum and the first substep loses part of the spin.
TEST(SceneSetup, ASpinningBodyKeepsItsRotationThroughTheFirstSubstep) {
  const Scene scene = parse_scene(cube_scene("angular_velocity = [0, 0, \"omega\"]"), "spin.toml");
  SceneSetup setup = build_scene(scene);
  const Index n = setup.particles.count();
  Vec3<double> center = Vec3<double>::zero();
  for (Index p = 0; p < n; ++p) center += at(setup.particles.x, n, p) * (1.0 / double(n));
  auto largest_error_after_a_substep = [&](const mpm::ParticleInit& init) {
    engine::FullOrderSim sim(Exec::cpu(), setup.config, init);
    sim.substep(1e-4f);
    const std::vector<float> v = sim.particles().velocities_in_initial_order(sim.exec());
    double largest = 0.0;
    for (Index p = 0; p < n; ++p) {
      // G2P reads the grid at the particle's place before it moves.
      const Vec3<double> expected = cross(Vec3<double>(0.0, 0.0, 3.0), at(init.x, n, p) - center);
      largest = std::max(largest, norm(at(v, n, p) - expected));
    }
    return largest;
  };
  const double speed = 3.0 * 0.1 * std::sqrt(2.0);  // at the cube's corners
  EXPECT_LT(largest_error_after_a_substep(setup.particles), 1e-4 * speed);
  mpm::ParticleInit without_c = setup.particles;
  without_c.C.clear();
  EXPECT_GT(largest_error_after_a_substep(without_c), 1e-2 * speed);
}

// An object read from `points` (with `keys` added) in the cube scene, its shape line removed.
std::string points_scene(const std::string& file, const std::string& keys = "") {
  std::string text = cube_scene("points = \"" + file + "\"\n" + keys);
  const std::size_t shape = text.find("shape = {");
  return text.erase(shape, text.find('\n', shape) - shape);
}

void write_text(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

TEST(SceneSetup, APlyPointCloudGivesOneParticleAPointWithItsVelocityAndVolume) {
  test::ScratchFolder folder;
  const std::string ply = folder.file("cloud.ply");
  write_text(ply,
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
             "property double vx\nproperty double vy\nproperty double vz\nproperty float volume\nend_header\n"
             "0.4 0.5 0.5 1 0 0 1e-6\n0.5 0.5 0.5 0 2 0 2e-6\n0.6 0.5 0.5 0 0 3 1e-6\n");
  const SceneSetup setup = sample_scene(parse_scene(points_scene(ply, "velocity = [0, 0, 0.5]"), "cloud.toml"));
  const mpm::ParticleInit& init = setup.particles;
  ASSERT_EQ(init.count(), 3);
  EXPECT_NEAR(at(init.x, 3, 2)[0], 0.6, 1e-7);
  EXPECT_EQ(at(init.v, 3, 0), Vec3<double>(1.0, 0.0, 0.5));  // the file's plus the object's
  EXPECT_EQ(at(init.v, 3, 1), Vec3<double>(0.0, 2.0, 0.5));
  EXPECT_FLOAT_EQ(init.volume0[1], 2e-6f);
  EXPECT_FLOAT_EQ(init.mass[1], init.mass[0] * 2.0f);
  EXPECT_TRUE(init.C.empty());
}

TEST(SceneSetup, APointCloudWithoutVolumesNeedsParticleVolume) {
  test::ScratchFolder folder;
  const std::string ply = folder.file("bare.ply");
  write_text(ply,
             "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
             "end_header\n0.4 0.5 0.5\n0.5 0.5 0.5\n");
  const std::string missing = test::error_message([&] { sample_scene(parse_scene(points_scene(ply), "bare.toml")); });
  EXPECT_NE(missing.find("objects 'object0': points = " + ply + ": the file gives no volume per point"),
            std::string::npos)
      << missing;
  const SceneSetup setup = sample_scene(parse_scene(points_scene(ply, "particle_volume = 1e-6"), "bare.toml"));
  EXPECT_EQ(setup.particles.volume0, std::vector<float>(2, 1e-6f));
}

TEST(SceneSetup, BadPointFilesAreRefusedNamingTheObjectAndTheFile) {
  test::ScratchFolder folder;
  // An ascii file's reader refuses a "nan" token; a binary file's float is checked after reading.
  const std::string ply = folder.file("nan.ply");
  std::string bytes =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n";
  const float values[3] = {std::nanf(""), 0.5f, 0.5f};
  bytes.append(reinterpret_cast<const char*>(values), sizeof values);
  write_text(ply, bytes);
  const std::string nan =
      test::error_message([&] { sample_scene(parse_scene(points_scene(ply, "particle_volume = 1e-6"), "n.toml")); });
  EXPECT_NE(nan.find("objects 'object0': a particle at (nan, 0.5, 0.5) lies outside the domain's interior"),
            std::string::npos)
      << nan;
  const std::string moving = folder.file("nan_velocity.ply");
  std::string moving_bytes =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nproperty float vx\nproperty float vy\nproperty float vz\nend_header\n";
  const float moving_values[6] = {0.5f, 0.5f, 0.5f, 0.0f, std::nanf(""), 0.0f};
  moving_bytes.append(reinterpret_cast<const char*>(moving_values), sizeof moving_values);
  write_text(moving, moving_bytes);
  const std::string velocity =
      test::error_message([&] { sample_scene(parse_scene(points_scene(moving, "particle_volume = 1e-6"), "v.toml")); });
  EXPECT_NE(velocity.find("point 0 has a velocity that is not finite"), std::string::npos) << velocity;
  const std::string both = test::error_message([&] {
    parse_scene(cube_scene("points = \"" + ply + "\""), "both.toml");  // a shape as well
  });
  EXPECT_NE(both.find("objects[0].shape: an object read from `points` has no shape"), std::string::npos) << both;
  const std::string absent =
      test::error_message([&] { parse_scene(points_scene(folder.file("none.ply")), "absent.toml"); });
  EXPECT_NE(absent.find("no point file at"), std::string::npos) << absent;
}

TEST(SceneSetup, ASnapshotFrameGivesTheParticlesPositionsVelocitiesAndVolumes) {
  test::ScratchFolder folder;
  io::SnapshotHeader header;
  header.X = {0.4f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
  header.mass = {1.0f, 1.0f};
  header.volume0 = {1e-6f, 3e-6f};
  header.material = {0, 0};
  const std::string path = folder.file("earlier.h5");
  io::SnapshotWriter writer(path, header, io::kFieldX | io::kFieldV);
  io::FrameData frame;
  frame.x = header.X;
  frame.v.assign(6, 0.0f);
  writer.append_frame(frame);
  frame.x = {0.45f, 0.55f, 0.5f, 0.5f, 0.5f, 0.5f};
  frame.v = {0.1f, 0.2f, 0.0f, 0.0f, 0.0f, 0.0f};
  frame.time = 0.1;
  writer.append_frame(frame);
  writer.finish();
  const SceneSetup setup = sample_scene(parse_scene(points_scene(path, "points_frame = 1"), "later.toml"));
  const mpm::ParticleInit& init = setup.particles;
  ASSERT_EQ(init.count(), 2);
  EXPECT_NEAR(at(init.x, 2, 1)[0], 0.55, 1e-7);
  EXPECT_NEAR(at(init.v, 2, 0)[0], 0.1, 1e-7);
  EXPECT_EQ(init.volume0, header.volume0);
  const std::string past =
      test::error_message([&] { sample_scene(parse_scene(points_scene(path, "points_frame = 2"), "past.toml")); });
  EXPECT_NE(past.find("points_frame = 2, but the snapshot holds frames 0 .. 1"), std::string::npos) << past;
}

// A traction on the top face of a free cube (no gravity): the particles of its top layer carry it, each
// with its h² of the face, so the body's momentum grows at traction × face area, and the particles below
// carry none.
TEST(SceneSetup, ATractionPushesTheBodyWithTractionTimesTheLoadedArea) {
  // The cube [0.4, 0.6]³ sampled at h = 0.025 (dx 0.05, 2 per cell): the top layer at y = 0.5875.
  const Scene scene = parse_scene(cube_scene("", R"(
[[loads.tractions]]
name = "lid"
region = { type = "box", center = [0.5, 0.5875, 0.5], size = [0.3, 0.02, 0.3] }
traction = [0, -50, 10]
end = 0.01
)"),
                                  "lid.toml");
  ASSERT_EQ(scene.tractions.size(), 1u);
  const SceneSetup setup = build_scene(scene);
  const mpm::ParticleInit& init = setup.particles;
  const Index n = init.count();
  Index loaded = 0;
  for (Index p = 0; p < n; ++p) {
    const bool top = at(init.x, n, p)[1] > 0.58;
    EXPECT_EQ(init.traction[std::size_t(p)], top ? 0 : mpm::kNoTraction) << p;
    loaded += top;
  }
  ASSERT_EQ(loaded, 64);  // 8 × 8 particles on a 0.2 m face
  engine::FullOrderSim sim(Exec::cpu(), setup.config, init);
  sim.advance_to(0.02);  // the traction acts for the first 0.01 s only
  const std::vector<float> v = sim.particles().velocities_in_initial_order(sim.exec());
  Vec3<double> momentum = Vec3<double>::zero();
  for (Index p = 0; p < n; ++p) momentum += at(v, n, p) * double(init.mass[std::size_t(p)]);
  const double area = 0.2 * 0.2, duration = 0.01;
  EXPECT_NEAR(momentum[0], 0.0, 1e-6);
  EXPECT_NEAR(momentum[1], -50.0 * area * duration, 1e-3 * 50.0 * area * duration);
  EXPECT_NEAR(momentum[2], 10.0 * area * duration, 1e-3 * 50.0 * area * duration);
}

TEST(SceneSetup, ATractionWhoseRegionHoldsNoParticleIsRefused) {
  const std::string message = test::error_message([] {
    build_scene(parse_scene(cube_scene("", R"(
[[loads.tractions]]
region = { type = "sphere", center = [0.1, 0.1, 0.1], radius = 0.01 }
traction = [0, -50, 0]
)"),
                            "empty.toml"));
  });
  EXPECT_NE(message.find("loads.tractions 'traction0': its region holds no particle at t = 0"), std::string::npos)
      << message;
}

}  // namespace
}  // namespace romp::scene
