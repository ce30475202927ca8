// Offline training on an analytic family: the twisted bar is learnt to a test reconstruction error below 1%
// on the CPU, and a run stopped and resumed from its checkpoint ends bitwise where the uninterrupted one does.
#include "nn/rom/rom_trainer.h"

#include <gtest/gtest.h>

#include "nn/rom/rom_evaluation.h"
#include "nn/rom/rom_model_file.h"
#include "tests/nn/rom/twisted_bar.h"
#include "tests/support/scratch_folder.h"

namespace romp::nn::rom {
namespace {

TrainingSettings bar_settings() {
  TrainingSettings s;
  s.architecture.latent = 2;
  s.encoder_points = 0;
  s.epochs = 60;
  s.batch = 8;
  s.points = 128;
  s.seed = 1;
  return s;
}

// Three twists of five frames, the middle one held out: enough for a few epochs of a quick run.
void write_short_bar(const test::ScratchFolder& folder) {
  test::TwistedBar bar;
  bar.members = 3;
  bar.test_members = {1};
  bar.frames = 5;
  bar.write(folder.path());
}

TEST(RomTrainer, LearnsTheTwistedBarToBelowOnePercentOnHeldOutTwists) {
  torch::set_num_threads(1);  // deterministic and fair to the other tests ctest runs beside this one
  const test::ScratchFolder folder;
  test::TwistedBar().write(folder.path());
  TrainOptions options;
  options.settings = bar_settings();
  const RomDataset data = load_rom_dataset(folder.path().string(), {0, options.settings.seed, torch::kCPU});
  const TrainResult result = train_rom(data, options);
  const ReconstructionErrors& test = result.model.training.test_errors;
  EXPECT_LT(test.position, 0.01);
  EXPECT_LT(test.F, 0.1);
  EXPECT_EQ(result.model.training.epochs_done, options.settings.epochs);
}

TEST(RomTrainer, ResumedRunEndsBitwiseWhereTheUninterruptedOneDoes) {
  torch::set_num_threads(1);
  const test::ScratchFolder folder;
  write_short_bar(folder);
  TrainOptions options;
  options.settings = bar_settings();
  options.settings.epochs = 6;
  const RomDataset data = load_rom_dataset(folder.path().string(), {50, 3, torch::kCPU});
  options.settings.encoder_points = 50;
  options.settings.seed = 3;
  const TrainResult whole = train_rom(data, options);

  options.checkpoint = folder.file("model.h5.checkpoint");
  int epochs_seen = 0;
  const TrainResult stopped = train_rom(data, options, {}, [&] { return ++epochs_seen == 2; });
  ASSERT_TRUE(stopped.interrupted);
  EXPECT_EQ(stopped.model.training.epochs_done, 2);
  options.resume = true;
  std::vector<std::int64_t> reported;
  const TrainResult resumed = train_rom(data, options, [&](const EpochReport& r) { reported.push_back(r.epoch); });
  EXPECT_EQ(resumed.resumed_at, 2);
  EXPECT_EQ(reported.front(), 3);
  const std::vector<torch::Tensor> a = whole.model.parameters(), b = resumed.model.parameters();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(torch::equal(a[i], b[i])) << "parameter " << i;
  EXPECT_EQ(resumed.model.training.test_errors.position, whole.model.training.test_errors.position);
}

// Progress reports compare a few evenly spaced points per test snapshot (the record at the end compares all):
// an estimate close to the whole set's errors, and exactly them when asked for every point.
TEST(RomTrainer, ReportsEstimateTheTestErrorsFromAFewPoints) {
  torch::set_num_threads(1);
  const test::ScratchFolder folder;
  write_short_bar(folder);
  TrainOptions options;
  options.settings = bar_settings();
  options.settings.epochs = 4;
  options.report_points = 16;
  const RomDataset data = load_rom_dataset(folder.path().string(), {0, options.settings.seed, torch::kCPU});
  const std::int64_t P = data.X.size(0);
  std::vector<EpochReport> reports;
  const TrainResult result = train_rom(data, options, [&](const EpochReport& r) { reports.push_back(r); });
  ASSERT_FALSE(reports.empty());
  EXPECT_EQ(reports.back().points, P);
  EXPECT_EQ(reports.back().test_points, evaluated_points(P, 16));
  EXPECT_LE(reports.back().test_points, 16);

  const ReconstructionErrors all = reconstruction_errors(result.model, data.X, data.test);
  const ReconstructionErrors also_all =
      reconstruction_errors(result.model, data.X, data.test, DerivativeMethod::Analytic, P);
  EXPECT_EQ(also_all.position, all.position);
  EXPECT_EQ(also_all.F, all.F);
  EXPECT_EQ(all.position, result.model.training.test_errors.position);
  const ReconstructionErrors estimate =
      reconstruction_errors(result.model, data.X, data.test, DerivativeMethod::Analytic, P / 4);
  EXPECT_NEAR(estimate.position, all.position, 0.25 * all.position);
  EXPECT_NEAR(estimate.F, all.F, 0.25 * all.F);
  EXPECT_NE(estimate.position, all.position);  // fewer points were compared
}

TEST(RomTrainer, CheckpointOfOtherSettingsIsRefusedListingTheDifferences) {
  torch::set_num_threads(1);
  const test::ScratchFolder folder;
  test::TwistedBar bar;
  bar.members = 2;
  bar.frames = 3;
  bar.write(folder.path());
  TrainOptions options;
  options.settings = bar_settings();
  options.settings.epochs = 4;
  options.checkpoint = folder.file("model.h5.checkpoint");
  const RomDataset data = load_rom_dataset(folder.path().string(), {0, options.settings.seed, torch::kCPU});
  ASSERT_TRUE(train_rom(data, options, {}, [] { return true; }).interrupted);
  options.resume = true;
  options.settings.batch = 4;
  const std::string message = test::error_message([&] { train_rom(data, options); });
  EXPECT_NE(message.find("model.h5.checkpoint is from another training run"), std::string::npos) << message;
  EXPECT_NE(message.find("batch: 4 here, 8 in the other"), std::string::npos) << message;
}

}  // namespace
}  // namespace romp::nn::rom
