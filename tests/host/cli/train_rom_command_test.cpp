// `romp train-rom` end to end: a sweep folder in, a model file out that reads back with its record; an unusable
// folder and a --resume without a checkpoint exit 3 and say why; a --resume of a finished model does nothing.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "nn/rom/rom_model_file.h"
#include "tests/nn/rom/twisted_bar.h"
#include "tests/support/scratch_folder.h"

namespace romp::cli {
namespace {

struct Outcome {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

Outcome romp_train_rom(const test::ScratchFolder& folder, const std::string& arguments) {
  const std::string log = folder.file("romp.log");
  const int status = std::system(
      (std::string(ROMP_EXECUTABLE) + " --threads 1 train-rom " + arguments + " > " + log + " 2>&1").c_str());
  std::ostringstream output;
  output << std::ifstream(log).rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output.str()};
}

TEST(TrainRomCommand, WritesAModelThatReadsBackWithItsRecord) {
  const test::ScratchFolder folder;
  test::TwistedBar bar;
  bar.members = 3;
  bar.test_members = {1};
  bar.frames = 4;
  bar.write(folder.path() / "sweep");
  const std::string model = folder.file("bar.h5");
  const Outcome run = romp_train_rom(
      folder, folder.file("sweep") + " -o " + model + " --latent 2 --epochs 3 --encoder-points 50 --points 32");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("epoch 3/3"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(model + ".checkpoint"));
  const nn::rom::RomModel read = nn::rom::read_rom_model(model);
  EXPECT_EQ(read.map->architecture().latent, 2);
  EXPECT_EQ(read.training.epochs_done, 3);
  EXPECT_EQ(read.training.members.size(), 3u);
  EXPECT_TRUE(std::isfinite(read.training.test_errors.position));
  EXPECT_FALSE(read.training.commit.empty());
}

TEST(TrainRomCommand, FolderWithoutManifestExits3NamingIt) {
  const test::ScratchFolder folder;
  const Outcome run = romp_train_rom(folder, folder.path().string() + " -o " + folder.file("m.h5"));
  EXPECT_EQ(run.exit_code, 3) << run.output;
  EXPECT_NE(run.output.find("no manifest.json"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(folder.file("m.h5")));
}

TEST(TrainRomCommand, ResumeWithoutCheckpointExits3) {
  const test::ScratchFolder folder;
  const Outcome run = romp_train_rom(folder, folder.path().string() + " -o " + folder.file("m.h5") + " --resume");
  EXPECT_EQ(run.exit_code, 3) << run.output;
  EXPECT_NE(run.output.find("no checkpoint " + folder.file("m.h5.checkpoint")), std::string::npos) << run.output;
}

// As `romp run --resume` on a finished output: nothing to do, exit 0, the model untouched.
TEST(TrainRomCommand, ResumeOfAFinishedModelDoesNothing) {
  const test::ScratchFolder folder;
  const std::string model = folder.file("m.h5");
  std::ofstream(model) << "a finished model";
  const Outcome run = romp_train_rom(folder, folder.path().string() + " -o " + model + " --resume");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find(model + " is complete; nothing to resume"), std::string::npos) << run.output;
  std::ostringstream kept;
  kept << std::ifstream(model).rdbuf();
  EXPECT_EQ(kept.str(), "a finished model");
}

}  // namespace
}  // namespace romp::cli
