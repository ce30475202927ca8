// romp run: complete outputs, resume equivalent to an uninterrupted run (bitwise on one CPU
// thread), readable partial output when the simulation blows up, and every paper material.
#include "host/run/scene_runner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "host/engine/full_order_sim.h"
#include "host/scene/scene_parser.h"
#include "host/scene/toml_reader.h"
#include "nn/io/hdf5_file.h"
#include "nn/io/output_lock.h"
#include "nn/io/snapshot_layout.h"
#include "nn/io/snapshot_reader.h"
#include "nn/io/snapshot_writer.h"
#include "tests/host/rom_test_maps.h"
#include "tests/support/scratch_folder.h"

namespace romp::run {
namespace {

namespace fs = std::filesystem;

// The NCLaw cube at a coarse sampling, 8 frames of 10 steps each.
std::string cube_scene(const std::string& material, const std::string& extra = "") {
  return R"(
[domain]
size = [1.0, 1.0, 1.0]
dx = 0.05
[time]
end = 0.04
frame_rate = 200
dt = 5e-4
[boundary]
contact = "separate"
[materials.body]
preset = ")" +
         material + R"("
[[objects]]
velocity = [1.0, -1.5, -2.0]
angular_velocity = [4.0, 4.0, 4.0]
shape = { type = "box", center = [0.5, 0.5, 0.5], size = [0.5, 0.5, 0.5] }
sampling = { per_cell = 1 }
)" + extra;
}

class SceneRunner : public ::testing::Test {
 protected:
  RunOptions options(const std::string& name) const {
    RunOptions o;
    o.output = folder_.file(name);
    o.progress = false;
    return o;
  }
  test::ScratchFolder folder_;
};

TEST_F(SceneRunner, WritesEveryFrameAndLeavesOnlyTheFinishedFiles) {
  const scene::Scene scene = scene::parse_scene(cube_scene("jelly"), "cube.toml");
  const RunOptions o = options("cube.h5");
  const RunResult r = run_scene(Exec::cpu(), scene, o);
  EXPECT_FALSE(r.interrupted);
  EXPECT_EQ(r.output, o.output);
  EXPECT_EQ(r.frames_written, 8);
  EXPECT_EQ(r.substeps, 80);
  EXPECT_TRUE(fs::exists(o.output));
  EXPECT_TRUE(fs::exists(io::xdmf_path(o.output)));
  EXPECT_FALSE(fs::exists(io::partial_path(o.output)));
  EXPECT_FALSE(fs::exists(io::checkpoint_path(o.output)));
  // The substeps allocate nothing (FullOrderSim's test); the frames' captures do, 8 frames in 80 substeps.
  ASSERT_FALSE(r.diagnostics.empty());
  const std::string& traffic = r.diagnostics.back();
  EXPECT_EQ(traffic.rfind("host traffic per substep, frame output included: ", 0), 0u) << traffic;
  EXPECT_LT(std::stod(traffic.substr(traffic.find(": ") + 2)), 1.0) << traffic;
  const io::SnapshotReader reader(o.output);
  EXPECT_EQ(reader.frame_count(), 9);
  EXPECT_EQ(reader.header().scene, scene.resolved_text);
  EXPECT_NEAR(reader.read_frame(8).time, 0.04, 1e-12);
}

// Two runs of one output once interleaved their frames (the first exited 0 with half of them): while one
// run holds the output, another (or a --resume of it) is refused before it writes anything.
TEST_F(SceneRunner, ASecondRunOfTheSameOutputIsRefusedWhileTheFirstHoldsIt) {
  const scene::Scene scene = scene::parse_scene(cube_scene("jelly"), "cube.toml");
  RunOptions o = options("cube.h5");
  {
    const io::OutputLock first_run(o.output);
    for (const bool resume : {false, true}) {
      o.resume = resume;
      const std::string error = test::error_message([&] { run_scene(Exec::cpu(), scene, o); });
      EXPECT_NE(error.find(o.output + " is being written by process"), std::string::npos) << error;
      EXPECT_FALSE(fs::exists(io::partial_path(o.output)));
      EXPECT_FALSE(fs::exists(o.output));
    }
  }
  o.resume = false;
  EXPECT_EQ(run_scene(Exec::cpu(), scene, o).frames_written, 8);
  EXPECT_FALSE(fs::exists(o.output + ".lock"));
}

// An output that names a folder once failed only after the whole run, at the final rename.
TEST_F(SceneRunner, AnOutputThatIsAFolderIsRefusedBeforeTheRun) {
  const scene::Scene scene = scene::parse_scene(cube_scene("jelly"), "cube.toml");
  RunOptions o = options("folder.h5");
  fs::create_directories(o.output);
  try {
    run_scene(Exec::cpu(), scene, o);
    FAIL() << "accepted";
  } catch (const scene::SceneError& error) {
    EXPECT_NE(std::string(error.what()).find("the output is a folder"), std::string::npos) << error.what();
  }
  EXPECT_FALSE(fs::exists(io::partial_path(o.output)));
}

TEST_F(SceneRunner, ReducedRunWritesTheDecodedStateOfEveryMaterialPoint) {
  // The translation family g(X; x̂) = X + x̂ as the model: every frame is the initial body moved by x̂.
  const scene::Scene scene = scene::parse_scene(cube_scene("jelly"), "cube.toml");
  RunOptions o = options("reduced.h5");
  o.make_reduced = [](const Exec& exec, const scene::SceneSetup& setup) {
    return reduced_simulation(exec, setup.config, setup.particles, test::translation_map(), {0.0f, 0.0f, 0.0f},
                              engine::ReducedOptions{});
  };
  const RunResult r = run_scene(Exec::cpu(), scene, o);
  EXPECT_EQ(r.frames_written, 8);
  EXPECT_FALSE(fs::exists(io::checkpoint_path(o.output)));
  ASSERT_FALSE(r.diagnostics.empty());
  EXPECT_NE(r.diagnostics[0].find("80 substeps"), std::string::npos) << r.diagnostics[0];
  const io::SnapshotReader reader(o.output);
  ASSERT_EQ(reader.frame_count(), 9);
  const std::vector<float>& X = reader.header().X;
  const Index n = reader.header().particle_count();
  const io::FrameData last = reader.read_frame(8);
  // A rigid translation: every point moved by the same vector, and F = I.
  for (Index p = 0; p < n; ++p)
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(last.x[a * n + p] - X[a * n + p], last.x[a * n] - X[a * n], 1e-6f);
      EXPECT_EQ(last.F[(4 * a) * n + p], 1.0f);
    }
  EXPECT_GT(std::fabs(last.x[0] - X[0]), 0.02f);  // it moved at 1 m/s for 0.04 s
  o.resume = true;
  EXPECT_THROW(run_scene(Exec::cpu(), scene, o), Error);
}

// --output-points in a reduced-order run: the map decoded at points the scene never sampled (the ROM
// paper's super-resolution), with F.
TEST_F(SceneRunner, OutputPointsOfAReducedRunAreDecodedThere) {
  io::SnapshotHeader points;
  points.X = {0.3f, 0.55f, 0.7f, 0.31f, 0.45f, 0.69f, 0.5f, 0.5f, 0.51f};  // three points, as planes
  points.mass = points.volume0 = {1.0f, 1.0f, 1.0f};
  points.material = {0, 0, 0};
  io::SnapshotWriter(folder_.file("points.h5"), points, io::kFieldX).finish();
  const scene::Scene scene = scene::parse_scene(cube_scene("jelly"), "cube.toml");
  RunOptions o = options("decoded.h5");
  o.output_points = folder_.file("points.h5");
  o.make_reduced = [](const Exec& exec, const scene::SceneSetup& setup) {
    return reduced_simulation(exec, setup.config, setup.particles, test::translation_map(), {0.0f, 0.0f, 0.0f},
                              engine::ReducedOptions{});
  };
  run_scene(Exec::cpu(), scene, o);
  const io::SnapshotReader reader(o.output);
  EXPECT_EQ(reader.header().X, points.X);
  EXPECT_EQ(reader.fields(), io::kStateFields);
  const io::FrameData last = reader.read_frame(8);
  ASSERT_EQ(last.x.size(), 9u);
  // g(X; x̂) = X + x̂: the three points moved by the same x̂, which moved at about 1 m/s for 0.04 s.
  for (int a = 0; a < 3; ++a)
    for (int p = 1; p < 3; ++p)
      EXPECT_NEAR(last.x[3 * a + p] - points.X[3 * a + p], last.x[3 * a] - points.X[3 * a], 1e-6f);
  EXPECT_GT(std::fabs(last.x[0] - points.X[0]), 0.02f);
  EXPECT_EQ(last.F[0], 1.0f);
}

// --output-points: frames at another snapshot's material points. In a full-order run they are tracers,
// which at the scene's own material points follow the particles; the output takes their reference
// state and holds x and v only; a checkpoint could not carry them, so no resume.
TEST_F(SceneRunner, OutputPointsOfAFullOrderRunAreTracers) {
  const scene::Scene scene = scene::parse_scene(cube_scene("jelly"), "cube.toml");
  const RunOptions reference = options("reference.h5");
  run_scene(Exec::cpu(), scene, reference);
  RunOptions o = options("tracers.h5");
  o.output_points = reference.output;
  const RunResult r = run_scene(Exec::cpu(), scene, o);
  EXPECT_EQ(r.frames_written, 8);
  EXPECT_FALSE(fs::exists(io::checkpoint_path(o.output)));
  const io::SnapshotReader truth(reference.output), tracers(o.output);
  EXPECT_EQ(tracers.header().X, truth.header().X);
  EXPECT_EQ(tracers.header().mass, truth.header().mass);
  EXPECT_EQ(tracers.fields(), io::kFieldX | io::kFieldV);
  ASSERT_EQ(tracers.frame_count(), truth.frame_count());
  const io::FrameData a = tracers.read_frame(8), b = truth.read_frame(8);
  ASSERT_EQ(a.x.size(), b.x.size());
  for (std::size_t i = 0; i < a.x.size(); ++i) EXPECT_NEAR(a.x[i], b.x[i], 1e-6f) << "value " << i;
  o.resume = true;
  EXPECT_THROW(run_scene(Exec::cpu(), scene, o), Error);
}

// A --output-points file that is not a snapshot is invalid input (exit 3 in romp run) naming the option
// and the file, and no output is left.
TEST_F(SceneRunner, OutputPointsThatAreNotASnapshotAreRefusedByName) {
  const scene::Scene scene = scene::parse_scene(cube_scene("jelly"), "cube.toml");
  RunOptions o = options("tracers.h5");
  o.output_points = folder_.file("points.h5");
  std::ofstream(o.output_points) << "not HDF5\n";
  try {
    run_scene(Exec::cpu(), scene, o);
    FAIL() << "a file that is not a snapshot was taken for points";
  } catch (const scene::SceneError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("--output-points"), std::string::npos) << message;
    EXPECT_NE(message.find(o.output_points), std::string::npos) << message;
  }
  EXPECT_FALSE(fs::exists(o.output));
  EXPECT_FALSE(fs::exists(io::partial_path(o.output)));
}

// Points whose reference positions are not finite (an all-NaN snapshot once gave NaN frames) or lie
// outside the domain are refused by name before the run.
TEST_F(SceneRunner, OutputPointsOutsideTheDomainOrNotFiniteAreRefused) {
  const scene::Scene scene = scene::parse_scene(cube_scene("jelly"), "cube.toml");
  const RunOptions reference = options("reference.h5");
  run_scene(Exec::cpu(), scene, reference);
  for (const float bad : {std::nanf(""), 2.0f}) {
    {
      io::hdf5::File file = io::hdf5::File::open(reference.output, io::hdf5::Mode::ReadWrite, "snapshot");
      const io::hdf5::Shape shape = file.dataset_shape("particles/X");
      std::vector<float> X = file.read_dataset<float>("particles/X", shape);
      X[3 * 17 + 1] = bad;  // point 17's y
      file.remove("particles/X");
      file.write_dataset("particles/X", shape, X);
    }
    RunOptions o = options("tracers.h5");
    o.output_points = reference.output;
    try {
      run_scene(Exec::cpu(), scene, o);
      FAIL() << "X[1] = " << bad << " was taken";
    } catch (const scene::SceneError& error) {
      EXPECT_NE(std::string(error.what()).find("point 17 has X[1] = "), std::string::npos) << error.what();
    }
    EXPECT_FALSE(fs::exists(io::partial_path(o.output)));
  }
}

// Runs `scene` whole and in two parts (stopped after frame 3, resumed) on one CPU thread, and checks
// that both wrote the same frames bit for bit.
void expect_resume_is_bitwise(const scene::Scene& scene, const test::ScratchFolder& folder) {
  const auto options = [&](const std::string& name) {
    RunOptions o;
    o.output = folder.file(name);
    o.progress = false;
    return o;
  };
  const Exec one_thread = Exec::cpu(1);
  RunOptions whole = options("whole.h5");
  run_scene(one_thread, scene, whole);

  RunOptions parts = options("parts.h5");
  parts.stop_at_frame = 3;
  const RunResult first = run_scene(one_thread, scene, parts);
  EXPECT_TRUE(first.interrupted);
  EXPECT_EQ(first.last_frame, 3);
  EXPECT_FALSE(fs::exists(parts.output));
  EXPECT_TRUE(fs::exists(io::partial_path(parts.output)));
  parts.stop_at_frame = -1;
  parts.resume = true;
  const RunResult second = run_scene(one_thread, scene, parts);
  EXPECT_FALSE(second.interrupted);
  EXPECT_EQ(second.first_frame, 3);
  EXPECT_EQ(second.frames_written, 5);

  const io::SnapshotReader a(whole.output), b(parts.output);
  ASSERT_EQ(a.frame_count(), b.frame_count());
  for (std::int64_t k = 0; k < a.frame_count(); ++k) {
    const io::FrameData fa = a.read_frame(k), fb = b.read_frame(k);
    EXPECT_EQ(fa.time, fb.time);
    EXPECT_EQ(fa.step, fb.step);
    EXPECT_EQ(fa.x, fb.x) << "frame " << k;
    EXPECT_EQ(fa.v, fb.v) << "frame " << k;
    EXPECT_EQ(fa.F, fb.F) << "frame " << k;
    EXPECT_EQ(fa.C, fb.C) << "frame " << k;
    EXPECT_EQ(fa.Jp, fb.Jp) << "frame " << k;
    EXPECT_EQ(fa.plastic_strain, fb.plastic_strain) << "frame " << k;
  }
  // Resuming a finished run does nothing.
  const RunResult third = run_scene(one_thread, scene, parts);
  EXPECT_EQ(third.frames_written, 0);
}

// The sand's plastic state (J_p and the plastic strain) is part of what a checkpoint restores.
const char* const kPlasticOutput = R"(
[output]
fields = ["x", "v", "F", "C", "Jp", "plastic_strain"]
)";

TEST_F(SceneRunner, ResumedRunIsBitwiseTheUninterruptedRun) {
  expect_resume_is_bitwise(scene::parse_scene(cube_scene("sand", kPlasticOutput), "cube.toml"), folder_);
}

// Sand thrown against the walls flows: its return maps change the volume (J_p) and remove strain,
// accumulated per particle from 1 and 0; an elastic scene has no plastic state to write.
TEST_F(SceneRunner, SandWritesItsPlasticStateAndJellyHasNone) {
  const RunOptions o = options("sand.h5");
  run_scene(Exec::cpu(), scene::parse_scene(cube_scene("sand", kPlasticOutput), "cube.toml"), o);
  const io::SnapshotReader reader(o.output);
  const io::FrameData first = reader.read_frame(0), last = reader.read_frame(reader.frame_count() - 1);
  const std::size_t n = std::size_t(reader.particle_count());
  EXPECT_EQ(first.Jp, std::vector<float>(n, 1.0f));
  EXPECT_EQ(first.plastic_strain, std::vector<float>(n, 0.0f));
  std::size_t flowed = 0;
  for (std::size_t p = 0; p < n; ++p) {
    EXPECT_GE(last.plastic_strain[p], 0.0f);
    EXPECT_GT(last.Jp[p], 0.0f);
    flowed += last.plastic_strain[p] > 0.0f && last.Jp[p] != 1.0f;
  }
  EXPECT_GT(flowed, n / 10) << "of " << n;
  const std::string message = test::error_message([&] {
    run_scene(Exec::cpu(), scene::parse_scene(cube_scene("jelly", kPlasticOutput), "cube.toml"), options("j.h5"));
  });
  EXPECT_NE(message.find("output.fields Jp, plastic_strain: no particle of this run keeps a plastic state"),
            std::string::npos)
      << message;
}

// With particle domains the checkpoint also carries the corners, the CFL's stiffening and which
// particles have lost their domains: the thrown cube with lattice domains, lower so that it is
// squeezed against the floor before the checkpoint, its step from the CFL condition, a slab of it
// released early, resumes bit for bit.
TEST_F(SceneRunner, ResumedRunWithParticleDomainsIsBitwiseTheUninterruptedRun) {
  std::string text = cube_scene("jelly");
  text.replace(text.find("dt = 5e-4"), 9, "cfl = 0.5\nmax_dt = 5e-3");  // the CFL step binds, not max_dt
  text.replace(text.find("sampling = { per_cell = 1 }"), 27, "sampling = { per_cell = 1 }\ndomains = true");
  text.replace(text.find("center = [0.5, 0.5, 0.5]"), 24, "center = [0.5, 0.42, 0.5]");
  text.replace(text.find("velocity = [1.0, -1.5, -2.0]"), 28, "velocity = [1.0, -6.0, -2.0]");  // hard into the floor
  // A slab of it loses its domains before the checkpoint: which ones did is part of the state.
  text +=
      "[[domain_release]]\nregion = { type = \"box\", center = [0.5, 0.42, 0.5], size = [1.0, 0.1, 1.0] }\n"
      "end = 0.01\n";
  expect_resume_is_bitwise(scene::parse_scene(text, "cube.toml"), folder_);
}

TEST_F(SceneRunner, ResumeRefusesACheckpointOfAnotherScene) {
  RunOptions o = options("cube.h5");
  o.stop_at_frame = 2;
  run_scene(Exec::cpu(), scene::parse_scene(cube_scene("jelly"), "cube.toml"), o);
  o.stop_at_frame = -1;
  o.resume = true;
  EXPECT_THROW(run_scene(Exec::cpu(), scene::parse_scene(cube_scene("sand"), "cube.toml"), o), Error);
}

TEST_F(SceneRunner, BlowUpStopsWithTheStageAndKeepsTheFramesWritten) {
  // A stiff body with a time step far above its CFL limit.
  std::string text = cube_scene("jelly");
  text.replace(text.find("dt = 5e-4"), 9, "dt = 2e-3");
  text.replace(text.find("end = 0.04"), 10, "end = 1.0");
  text.replace(text.find("preset = \"jelly\""), 16, "preset = \"jelly\"\nyoungs_modulus = 1e9");
  const scene::Scene scene = scene::parse_scene(text, "stiff.toml");
  const RunOptions o = options("stiff.h5");
  try {
    run_scene(Exec::cpu(), scene, o);
    FAIL() << "the run should have gone non-finite";
  } catch (const engine::NonFiniteError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("non-finite value at step"), std::string::npos) << message;
    EXPECT_NE(message.find(io::partial_path(o.output)), std::string::npos) << message;
    const io::SnapshotReader partial(io::partial_path(o.output));
    EXPECT_GE(partial.frame_count(), 1);
    for (float x : partial.read_frame(partial.frame_count() - 1).x) ASSERT_TRUE(std::isfinite(x));
  }
  EXPECT_FALSE(fs::exists(o.output));
}

TEST_F(SceneRunner, EveryPaperMaterialStaysFiniteAndInsideTheBox) {
  for (const char* material : {"jelly", "sand", "plasticine", "water"}) {
    const scene::Scene scene = scene::parse_scene(cube_scene(material), std::string(material) + ".toml");
    const RunResult r = run_scene(Exec::cpu(), scene, options(std::string(material) + ".h5"));
    const io::FrameData last = io::SnapshotReader(r.output).read_frame(8);
    for (float x : last.x) {
      ASSERT_GT(x, 0.0f) << material;
      ASSERT_LT(x, 1.0f) << material;
    }
    // Plastic materials run the return map (in G2P's stage, g2p_plasticity), elastic ones do not.
    bool plasticity = false;
    for (const auto& [stage, seconds] : r.stage_seconds) plasticity = plasticity || stage == "g2p_plasticity";
    EXPECT_EQ(plasticity, std::string(material) != "jelly") << material;
  }
}

}  // namespace
}  // namespace romp::run
