// romp learn-law: trains on a `romp run` snapshot, writes a readable law file and removes its
// checkpoint; --resume continues a checkpoint and refuses to start without one.
#include "host/learn_law_command.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "host/nclaw/ground_truth.h"
#include "host/run/scene_runner.h"
#include "host/scene/scene_parser.h"
#include "kernels/core/error.h"
#include "nn/nclaw/law_file.h"
#include "nn/nclaw/law_trainer.h"
#include "tests/support/scratch_folder.h"

namespace romp {
namespace {

// A 4³-particle cube falling onto the floor, one frame per substep for 10 substeps.
constexpr const char* kScene = R"(
[domain]
size = [1.0, 1.0, 1.0]
dx = 0.1
[time]
end = 0.01
frame_rate = 1000
dt = 1e-3
[boundary]
wall_cells = 3
contact = "separate"
[materials.body]
preset = "jelly"
[[objects]]
velocity = [0.0, -2.0, 0.0]
shape = { type = "box", center = [0.5, 0.45, 0.5], size = [0.2, 0.2, 0.2] }
sampling = { per_cell = 2 }
)";

class LearnLawCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    run::RunOptions run_options;
    run_options.output = folder_.file("cube.h5");
    run_options.progress = false;
    run::run_scene(Exec::cpu(), scene::parse_scene(kScene, "cube.toml"), run_options);
    options_.trajectory = run_options.output;
    options_.output = folder_.file("law.h5");
    options_.epochs = 2;
    options_.steps = 10;
  }
  test::ScratchFolder folder_;
  LearnLawOptions options_;
};

TEST_F(LearnLawCommand, WritesTheLawFileAndRemovesItsCheckpoint) {
  EXPECT_EQ(learn_law(DeviceChoice::Cpu, 1, options_), 0);
  const nn::LawFile law = nn::read_law_file(options_.output);
  EXPECT_EQ(law.training.trajectory, options_.trajectory);
  EXPECT_EQ(law.training.steps, 10);
  EXPECT_EQ(law.training.loss.size(), 2u);
  EXPECT_GT(law.training.reconstruction_error, 0.0);
  EXPECT_FALSE(std::filesystem::exists(options_.output + ".checkpoint"));
}

TEST_F(LearnLawCommand, ResumeContinuesACheckpointAndNeedsOne) {
  LearnLawOptions resume = options_;
  resume.resume = true;
  EXPECT_THROW(learn_law(DeviceChoice::Cpu, 1, resume), Error);
  // One epoch done, as an interrupted run leaves it.
  const nclaw::GroundTruth truth = nclaw::read_ground_truth(options_.trajectory, options_.steps);
  nn::TrainingOptions training;
  training.epochs = options_.epochs;
  training.steps = options_.steps;
  nn::LawTrainer trainer(truth.config, truth.trajectory, training);
  const double first_loss = trainer.train_epoch().loss;
  trainer.save_checkpoint(options_.output + ".checkpoint");
  EXPECT_EQ(learn_law(DeviceChoice::Cpu, 1, resume), 0);
  const nn::LawFile law = nn::read_law_file(options_.output);
  ASSERT_EQ(law.training.loss.size(), 2u);
  EXPECT_EQ(law.training.loss[0], first_loss);
}

}  // namespace
}  // namespace romp
