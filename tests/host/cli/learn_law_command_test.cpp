// romp learn-law: trains on a `romp run` snapshot, writes a readable law file and removes its
// checkpoint; --resume continues a checkpoint and refuses to start without one.
#include "host/cli/learn_law_command.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "host/nclaw/ground_truth.h"
#include "host/run/scene_runner.h"
#include "host/scene/scene_parser.h"
#include "kernels/core/error.h"
#include "nn/nclaw/evaluation.h"
#include "nn/nclaw/law_file.h"
#include "nn/nclaw/law_trainer.h"
#include "tests/support/scratch_folder.h"

namespace romp::cli {
namespace {

// tests/data/scenes/thrown_cube.toml: a 4³-particle cube thrown onto the floor, one frame per substep.
std::string thrown_cube_scene() {
  std::ifstream in(ROMP_TEST_DATA_DIR "/scenes/thrown_cube.toml");
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

class LearnLawCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    run::RunOptions run_options;
    run_options.output = folder_.file("cube.h5");
    run_options.progress = false;
    run::run_scene(Exec::cpu(), scene::parse_scene(thrown_cube_scene(), "thrown_cube.toml"), run_options);
    options_.trajectory = run_options.output;
    options_.output = folder_.file("law.h5");
    options_.epochs = 2;
    options_.steps = 10;
  }
  test::ScratchFolder folder_;
  LearnLawOptions options_;
};

TEST_F(LearnLawCommand, WritesTheLawFileAndRemovesItsCheckpoint) {
  EXPECT_EQ(learn_law_command(DeviceChoice::Cpu, 1, options_), 0);
  const nn::nclaw::LawFile law = nn::nclaw::read_law_file(options_.output);
  EXPECT_EQ(law.training.trajectory, options_.trajectory);
  EXPECT_EQ(law.training.steps, 10);
  EXPECT_EQ(law.training.loss.size(), 2u);
  EXPECT_GT(law.training.reconstruction_error, 0.0);
  EXPECT_FALSE(std::filesystem::exists(options_.output + ".checkpoint"));
}

// --steps below the reconstruction error's frame stride once trained every epoch and then failed; it is
// refused before training, with nothing written.
TEST_F(LearnLawCommand, StepsBelowTheEvaluationStrideAreRefusedBeforeTraining) {
  options_.steps = nn::nclaw::kEvaluationFrameStride - 1;
  for (const std::string method : {"motion", "labeled"}) {
    options_.method = method;
    try {
      learn_law_command(DeviceChoice::Cpu, 1, options_);
      FAIL() << method << ": accepted";
    } catch (const CLI::ValidationError& error) {
      EXPECT_NE(std::string(error.what()).find("measured every 5 substeps, so --steps must be at least that, got 4"),
                std::string::npos)
          << error.what();
    }
    EXPECT_FALSE(std::filesystem::exists(options_.output));
    EXPECT_FALSE(std::filesystem::exists(options_.output + ".checkpoint"));
  }
}

TEST_F(LearnLawCommand, ResumeContinuesACheckpointAndNeedsOne) {
  LearnLawOptions resume = options_;
  resume.resume = true;
  EXPECT_THROW(learn_law_command(DeviceChoice::Cpu, 1, resume), Error);
  // One epoch done, as an interrupted run leaves it.
  const nclaw::GroundTruth truth = nclaw::read_ground_truth(options_.trajectory, options_.steps);
  nn::nclaw::TrainingOptions training;
  training.epochs = options_.epochs;
  training.steps = options_.steps;
  nn::nclaw::LawTrainer trainer(truth.config, truth.trajectory, training);
  const double first_loss = trainer.train_epoch().loss;
  trainer.save_checkpoint(options_.output + ".checkpoint");
  EXPECT_EQ(learn_law_command(DeviceChoice::Cpu, 1, resume), 0);
  const nn::nclaw::LawFile law = nn::nclaw::read_law_file(options_.output);
  ASSERT_EQ(law.training.loss.size(), 2u);
  EXPECT_EQ(law.training.loss[0], first_loss);
}

// --teacher-forcing-first/-last and --velocity-weight reach the trainer: the first epoch's loss is that
// of a trainer given the same options, not the default one's; and a checkpoint of other options is refused.
TEST_F(LearnLawCommand, PassesTheScheduleAndTheVelocityWeightToTheTrainer) {
  options_.epochs = 1;
  options_.teacher_forcing_first = options_.teacher_forcing_last = 4;
  options_.velocity_weight = 0.01;
  EXPECT_EQ(learn_law_command(DeviceChoice::Cpu, 1, options_), 0);
  const double loss = nn::nclaw::read_law_file(options_.output).training.loss.at(0);

  const nclaw::GroundTruth truth = nclaw::read_ground_truth(options_.trajectory, options_.steps);
  nn::nclaw::TrainingOptions training;
  training.epochs = 1;
  training.steps = options_.steps;
  const double default_loss = nn::nclaw::LawTrainer(truth.config, truth.trajectory, training).train_epoch().loss;
  training.teacher_forcing_first = training.teacher_forcing_last = 4;
  training.velocity_weight = 0.01;
  nn::nclaw::LawTrainer same(truth.config, truth.trajectory, training);
  EXPECT_EQ(loss, same.train_epoch().loss);
  EXPECT_NE(loss, default_loss);

  same.save_checkpoint(options_.output + ".checkpoint");
  LearnLawOptions other = options_;
  other.resume = true;
  other.velocity_weight = 0.02;
  EXPECT_THROW(learn_law_command(DeviceChoice::Cpu, 1, other), Error);
}

// The labeled oracle fits the jelly's (F, P) pairs, so that its free rollout follows the trajectory
// far better than the same laws before the fit, and for an elastic material makes the plastic law F itself.
TEST_F(LearnLawCommand, LabeledOracleFitsTheGroundTruthsStress) {
  options_.method = "labeled";
  options_.epochs = 60;
  options_.pair_stride = 2;
  EXPECT_EQ(learn_law_command(DeviceChoice::Cpu, 1, options_), 0);
  nn::nclaw::LawFile law = nn::nclaw::read_law_file(options_.output);
  ASSERT_EQ(law.training.loss.size(), 60u);
  EXPECT_LT(law.training.loss.back(), 0.1 * law.training.loss.front());
  const nclaw::GroundTruth truth = nclaw::read_ground_truth(options_.trajectory);
  const nn::diffmpm::DiffMpm sim(truth.config, truth.trajectory.mass, truth.trajectory.volume);
  const double untrained = nn::nclaw::position_error(
      sim, truth.trajectory, nn::nclaw::seeded_laws(options_.seed, torch::kFloat32).constitutive(), 10);
  EXPECT_LT(law.training.reconstruction_error, 0.01 * untrained);  // measured: 9.0e-12 against 3.1e-8 m²
  const torch::Tensor F = torch::eye(3).reshape({9, 1}) + 0.1 * torch::randn({9, 8});
  EXPECT_TRUE(torch::equal(law.laws.plastic->forward(F), F));
}

// System identification writes a material table a scene can use, with E and ν found near the jelly's.
TEST_F(LearnLawCommand, SystemIdentificationWritesASceneMaterial) {
  options_.method = "system-identification";
  options_.epochs = 80;  // from the default first guess E = 3e4 Pa, nu = 0.3
  EXPECT_THROW(learn_law_command(DeviceChoice::Cpu, 1, options_), CLI::ValidationError);  // law.h5: not a .toml
  options_.output = folder_.file("identified.toml");
  EXPECT_EQ(learn_law_command(DeviceChoice::Cpu, 1, options_), 0);
  std::ifstream in(options_.output);
  const std::string table((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string scene = thrown_cube_scene();
  scene.replace(scene.find("[materials.body]\npreset = \"jelly\"\n"), 34, table);
  const scene::Scene parsed = scene::parse_scene(scene, folder_.file("identified_scene.toml"));
  ASSERT_EQ(parsed.materials.size(), 1u);
  EXPECT_EQ(parsed.materials[0].model, material::MaterialModel::FixedCorotated);
  EXPECT_NEAR(parsed.materials[0].youngs_modulus, 1e5, 0.2e5);
  EXPECT_NEAR(parsed.materials[0].poissons_ratio, 0.2, 0.05);
}

}  // namespace
}  // namespace romp::cli
