// read_ground_truth on a `romp run` snapshot: the scene's constants, the frames, and the
// differentiable step with the jelly's law reproducing the engine's trajectory.
#include "host/nclaw/ground_truth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "host/run/scene_runner.h"
#include "host/scene/scene_parser.h"
#include "kernels/core/error.h"
#include "nn/diffmpm/rollout.h"
#include "nn/io/hdf5_file.h"
#include "nn/io/snapshot_layout.h"
#include "nn/nclaw/fixed_corotated.h"
#include "tests/support/scratch_folder.h"

namespace romp::nclaw {
namespace {

namespace fs = std::filesystem;

constexpr int64_t kFrames = 20;

// The NCLaw training cube (jelly) for 20 substeps, one frame each; `time` replaces the [time] table.
std::string cube_scene(const std::string& time = "end = 0.01\nframe_rate = 2000\ndt = 5e-4\n") {
  return R"(
[domain]
size = [1.0, 1.0, 1.0]
dx = 0.05
[time]
)" + time +
         R"(
[boundary]
wall_cells = 3
contact = "separate"
[materials.body]
preset = "jelly"
[[objects]]
velocity = [1.0, -1.5, -2.0]
angular_velocity = [4.0, 4.0, 4.0]
shape = { type = "box", center = [0.5, 0.5, 0.5], size = [0.5, 0.5, 0.5] }
sampling = { per_cell = 1 }
[loads]
gravity = [0.0, -9.8, 0.0]
)";
}

std::string run(const test::ScratchFolder& folder, const std::string& text, const std::string& name) {
  run::RunOptions options;
  options.output = folder.file(name);
  options.progress = false;
  return run::run_scene(Exec::cpu(), scene::parse_scene(text, name + ".toml"), options).output;
}

TEST(GroundTruth, ReadsTheSceneConstantsAndEveryFrame) {
  const test::ScratchFolder folder;
  const GroundTruth truth = read_ground_truth(run(folder, cube_scene(), "cube.h5"));
  EXPECT_DOUBLE_EQ(truth.config.fixed_dt, 5e-4);
  EXPECT_DOUBLE_EQ(truth.config.dx, 0.05);
  EXPECT_EQ(truth.config.domain_cells, (std::array<std::int32_t, 3>{20, 20, 20}));
  EXPECT_EQ(truth.config.gravity, Vec3<double>(0.0, -9.8, 0.0));
  EXPECT_EQ(truth.config.wall_cells, 3);
  EXPECT_EQ(truth.config.wall_contact, mpm::ContactType::Separate);
  EXPECT_EQ(truth.trajectory.frame_count(), kFrames + 1);
  EXPECT_EQ(truth.trajectory.particle_count(), 1000);
  EXPECT_EQ(read_ground_truth(folder.file("cube.h5"), 5).trajectory.frame_count(), 6);
  EXPECT_THROW(read_ground_truth(folder.file("cube.h5"), kFrames + 1), Error);
}

// The differentiable step is the engine's step: with the jelly's fixed corotated law (E = 1e5 Pa,
// ν = 0.2) it follows the engine's trajectory to float rounding.
TEST(GroundTruth, DifferentiableStepReproducesTheEngine) {
  const test::ScratchFolder folder;
  const GroundTruth truth = read_ground_truth(run(folder, cube_scene(), "cube.h5"));
  const nn::nclaw::Trajectory& t = truth.trajectory;
  const nn::diffmpm::DiffMpm sim(truth.config, t.mass, t.volume);
  const torch::Tensor youngs = torch::tensor(1e5f), poisson = torch::tensor(0.2f);
  const nn::diffmpm::ConstitutiveLaws jelly{
      [&](const torch::Tensor& F) { return nn::nclaw::fixed_corotated_stress(F, youngs, poisson); }, {}, {}};
  torch::NoGradGuard no_grad;
  const nn::diffmpm::Rollout replay = nn::diffmpm::rollout(sim, t.state(0), jelly, {kFrames, 0});
  const double error = (replay.positions - t.x.slice(0, 1)).abs().max().item<double>();
  std::printf("max |x_diffmpm - x_engine| over %lld substeps: %.3g m\n", (long long)kFrames, error);
  EXPECT_LE(error, 1e-5);
}

TEST(GroundTruth, RejectsFramesThatSkipSubsteps) {
  const test::ScratchFolder folder;
  const std::string path = run(folder, cube_scene("end = 0.01\nframe_rate = 400\ndt = 5e-4\n"), "coarse.h5");
  try {
    read_ground_truth(path);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("one frame per substep"), std::string::npos) << error.what();
  }
}

// A trajectory with a NaN or far-away coordinate once made the differentiable P2G write outside its grid
// (learn-law crashed): such a frame is refused when it is read, naming the frame and the particle.
TEST(GroundTruth, PositionsOutsideTheDomainOrNotFiniteAreRefused) {
  const test::ScratchFolder folder;
  const std::string clean = run(folder, cube_scene(), "cube.h5");
  const std::int64_t n = 1000;
  const auto corrupted = [&](std::int64_t frame, const std::string& field, std::int64_t row, float value) {
    const std::string path = folder.file("corrupted.h5");
    fs::copy_file(clean, path, fs::copy_options::overwrite_existing);
    io::hdf5::File file = io::hdf5::File::open(path, io::hdf5::Mode::ReadWrite, "snapshot");
    const std::string dataset = io::frame_group_name(frame) + "/" + field;
    const io::hdf5::Shape shape = file.dataset_shape(dataset);
    std::vector<float> values = file.read_dataset<float>(dataset, shape);
    values[std::size_t(row * std::int64_t(shape[1]) + 1)] = value;  // its second component
    file.remove(dataset);
    file.write_dataset(dataset, shape, values);
    return path;
  };
  const auto error = [](const std::string& path) { return test::error_message([&] { read_ground_truth(path); }); };
  const std::string nan_position = error(corrupted(7, "x", 42, std::nanf("")));
  EXPECT_NE(nan_position.find("frame 7, particle 42: x[1] = nan is outside the domain's interior [0.05, 0.95] m"),
            std::string::npos)
      << nan_position;
  const std::string far = error(corrupted(3, "x", n - 1, 1e6f));
  EXPECT_NE(far.find("frame 3, particle 999: x[1] = 1000000 is outside"), std::string::npos) << far;
  const std::string velocity = error(corrupted(0, "v", 5, std::numeric_limits<float>::infinity()));
  EXPECT_NE(velocity.find("frame 0, v of particle"), std::string::npos) << velocity;
  EXPECT_NO_THROW(read_ground_truth(clean));
}

}  // namespace
}  // namespace romp::nclaw
