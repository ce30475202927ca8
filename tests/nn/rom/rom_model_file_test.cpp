// The ROM model file: a written model reads back with bitwise-identical outputs and its whole record; damaged,
// truncated and foreign files are rejected with messages that name the file and the object.
#include "nn/rom/rom_model_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "nn/io/hdf5_file.h"
#include "nn/rom/rom_checkpoint.h"
#include "tests/support/scratch_folder.h"

namespace romp::nn::rom {
namespace {

// A dataset in memory: 40 points, one training member of 3 frames (displaced a little), one test member.
RomDataset small_dataset() {
  torch::manual_seed(3);
  RomDataset data;
  data.dir = "/sweeps/small";
  data.parameter_names = {"gravity", "speed"};
  data.members = {{0, {9.8, 1.0}, false, "member_000000.h5"}, {1, {4.0, 2.0}, true, "member_000001.h5"}};
  data.X = torch::rand({40, 3});
  data.encoder_indices = torch::arange(0, 40, 2, torch::kInt64);
  data.train.x = data.X + 0.05 * torch::randn({3, 40, 3});
  return data;
}

RomModel small_model(std::int64_t hidden_layers) {
  TrainingSettings settings;
  settings.architecture = {2, hidden_layers, 30};
  settings.encoder_points = 20;
  settings.seed = 17;
  RomModel model = initial_model(small_dataset(), settings);
  model.training.epochs_done = 12;
  model.training.train_errors = {0.01, 0.02, 0.3};
  model.training.romp_version = "0.1.0";
  model.training.commit = "abc1234";
  return model;
}

class RomModelFile : public ::testing::Test {
 protected:
  void SetUp() override { write_rom_model(path_, small_model(5)); }

  // Applies `edit` to the written file, then returns the error reading it gives: an unusable file (exit 3).
  template <class Edit>
  std::string error_after(Edit&& edit) {
    {
      io::hdf5::File file = io::hdf5::File::open(path_, io::hdf5::Mode::ReadWrite, "model");
      edit(file);
    }
    return test::error_message<io::UnusableFileError>([&] { read_rom_model(path_); });
  }

  test::ScratchFolder folder_;
  std::string path_ = folder_.file("model.h5");
};

TEST_F(RomModelFile, RoundTripGivesIdenticalOutputsAndRecord) {
  for (std::int64_t hidden_layers : {5, 0}) {
    const RomModel written = small_model(hidden_layers);
    write_rom_model(path_, written);
    // Written atomically: the model, and no temporary beside it.
    EXPECT_EQ(folder_.contents(), std::vector<std::string>{"model.h5"});
    const RomModel read = read_rom_model(path_);

    torch::manual_seed(5);
    const torch::Tensor xhat = torch::randn({64, 2}), X = torch::rand({64, 3}), x = torch::rand({3, 40, 3});
    torch::NoGradGuard no_grad;
    EXPECT_TRUE(torch::equal(written.map->forward(xhat, X), read.map->forward(xhat, X)));
    const ManifoldJacobians a = manifold_jacobians(*written.map, xhat, X, DerivativeMethod::Analytic, false);
    const ManifoldJacobians b = manifold_jacobians(*read.map, xhat, X, DerivativeMethod::Analytic, false);
    EXPECT_TRUE(torch::equal(a.F, b.F) && torch::equal(a.dx, b.dx));
    EXPECT_TRUE(torch::equal(written.encode(x), read.encode(x)));
    EXPECT_EQ(read.map->is_linear(), hidden_layers == 0);

    const TrainingRecord& r = read.training;
    EXPECT_EQ(r.sweep_dir, "/sweeps/small");
    EXPECT_EQ(r.parameter_names, written.training.parameter_names);
    EXPECT_EQ(r.members, written.training.members);
    EXPECT_EQ(r.particle_count, 40);
    EXPECT_TRUE(r.settings.differences(written.training.settings).empty());
    EXPECT_EQ(r.epochs_done, 12);
    EXPECT_EQ(r.train_errors.F, 0.02);
    EXPECT_TRUE(std::isnan(r.test_errors.position));
    EXPECT_EQ(r.commit, "abc1234");
  }
}

TEST_F(RomModelFile, MissingWeightIsRejectedNamingFileAndDataset) {
  const std::string message = error_after([](io::hdf5::File& file) { file.remove("/map/layer_2/weight"); });
  EXPECT_NE(message.find(path_), std::string::npos) << message;
  EXPECT_NE(message.find("/map/layer_2/weight"), std::string::npos) << message;
}

TEST_F(RomModelFile, WeightOfWrongShapeIsRejected) {
  const std::string message = error_after([](io::hdf5::File& file) {
    file.remove("/map/layer_3/weight");
    file.write_dataset("/map/layer_3/weight", {30, 31}, std::vector<float>(30 * 31, 0.0f));
  });
  EXPECT_NE(message.find(path_), std::string::npos) << message;
  EXPECT_NE(message.find("/map/layer_3/weight"), std::string::npos) << message;
  EXPECT_NE(message.find("shape"), std::string::npos) << message;
}

TEST_F(RomModelFile, NonFiniteWeightIsRejected) {
  const std::string message = error_after([](io::hdf5::File& file) {
    std::vector<float> bias(2, 0.0f);  // r = 2
    bias[1] = std::nanf("");
    file.remove("/encoder/linear_1/bias");
    file.write_dataset("/encoder/linear_1/bias", {2}, bias);
  });
  EXPECT_NE(message.find("/encoder/linear_1/bias: not finite"), std::string::npos) << message;
}

TEST_F(RomModelFile, InconsistentArchitectureIsRejected) {
  const std::string message = error_after([](io::hdf5::File& file) {
    io::hdf5::Group map = file.open_group("map");
    map.write_attribute("kind", "linear");
  });
  EXPECT_NE(message.find(path_), std::string::npos) << message;
  EXPECT_NE(message.find("/map"), std::string::npos) << message;
}

// Sizes come from the file before any module is built: a hostile width, depth, latent or encoder size is
// refused by name before it can ask for terabytes.
TEST_F(RomModelFile, SizesBeyondAnyModelAreRejectedBeforeAllocating) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"map", "width"}, {"map", "hidden_layers"}, {"encoder", "points"}, {"", "latent"}};
  for (const auto& [group_name, attribute] : cases) {
    write_rom_model(path_, small_model(5));  // one size wrong at a time
    const std::string message = error_after([&, group = group_name, name = attribute](io::hdf5::File& file) {
      if (group.empty())
        file.write_attribute(name, std::int64_t(1) << 40);
      else
        file.open_group(group).write_attribute(name, std::int64_t(1) << 40);
    });
    EXPECT_NE(message.find(attribute + ": 1099511627776 is outside ["), std::string::npos) << message;
  }
}

// The training record's member count comes from a dataset's shape: more members than a sweep may have (their
// values would fill 1,000,000 doubles) is refused before the values are read.
TEST_F(RomModelFile, MoreMembersThanASweepHoldsAreRejectedBeforeReading) {
  const std::string message = error_after([](io::hdf5::File& file) {
    file.remove("/training/members/index");
    file.write_dataset("/training/members/index", {500001}, std::vector<std::int64_t>(500001, 0));
  });
  EXPECT_NE(message.find("500001 members of 2 parameters: a sweep holds at most 1000000 values"), std::string::npos)
      << message;
}

// The model fuzzer's seeds (tests/fuzz/corpus/model) are models this version reads: an MLP map with an encoder
// of one convolution, and the linear baseline.
TEST(RomModelFuzzSeeds, AreModelsThisVersionReads) {
  const RomModel mlp = read_rom_model(std::string(ROMP_MODEL_SEED_DIR) + "/model_mlp.h5");
  EXPECT_EQ(mlp.map->architecture().hidden_layers, 2);
  EXPECT_EQ(mlp.encoder->convolutions().size(), 1u);
  EXPECT_TRUE(read_rom_model(std::string(ROMP_MODEL_SEED_DIR) + "/model_linear.h5").map->is_linear());
}

TEST_F(RomModelFile, TruncatedFileIsRejectedNamingIt) {
  std::filesystem::resize_file(path_, std::filesystem::file_size(path_) / 2);
  const std::string message = test::error_message([&] { read_rom_model(path_); });
  EXPECT_NE(message.find("model " + path_), std::string::npos) << message;
}

TEST_F(RomModelFile, OtherHdf5FilesAreNotModels) {
  write_rom_checkpoint(folder_.file("run.checkpoint"), small_model(5), Adam(small_model(5).parameters()));
  const std::string message = test::error_message([&] { read_rom_model(folder_.file("run.checkpoint")); });
  EXPECT_NE(message.find("not a romp ROM model"), std::string::npos) << message;
  EXPECT_NE(test::error_message([&] { read_rom_model(folder_.file("absent.h5")); }).find("no such file"),
            std::string::npos);
}

}  // namespace
}  // namespace romp::nn::rom
