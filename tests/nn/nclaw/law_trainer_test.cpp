// LawTrainer: the schedules, a short training that lowers the loss, and resuming from a checkpoint
// bitwise as if uninterrupted.
#include <gtest/gtest.h>
#include <omp.h>

#include <vector>

#include "kernels/core/error.h"
#include "nn/nclaw/law_trainer.h"
#include "nn/nclaw/training_schedule.h"
#include "tests/nn/nclaw/tiny_trajectory.h"
#include "tests/support/scratch_folder.h"

namespace romp::nn::nclaw {
namespace {

TEST(TrainingSchedule, CosineAnnealingRunsFromFirstToLast) {
  EXPECT_DOUBLE_EQ(cosine_anneal(1.0, 0.0, 0, 300), 1.0);
  EXPECT_DOUBLE_EQ(cosine_anneal(1.0, 0.0, 150, 300), 0.5);
  EXPECT_NEAR(cosine_anneal(1.0, 0.0, 300, 300), 0.0, 1e-15);
  EXPECT_GT(cosine_anneal(1.0, 0.0, 1, 300), cosine_anneal(1.0, 0.0, 2, 300));
}

TEST(TrainingSchedule, TeacherForcingPeriodRisesFrom25To200) {
  EXPECT_EQ(teacher_forcing_period(25, 200, 0, 300), 25);
  EXPECT_EQ(teacher_forcing_period(25, 200, 150, 300), 113);  // 112.5 rounded away from zero
  EXPECT_EQ(teacher_forcing_period(25, 200, 300, 300), 200);
}

TrainingOptions short_training(int64_t epochs, int64_t steps) {
  TrainingOptions options;
  options.epochs = epochs;
  options.steps = steps;
  options.teacher_forcing_first = 10;
  options.teacher_forcing_last = 20;
  return options;
}

// One CPU thread: the P2G scatter's float sums are then in one fixed order, so every run trains
// the same weights.
class LawTraining : public ::testing::Test {
 protected:
  void SetUp() override {
    omp_set_num_threads(1);
    torch::set_num_threads(1);
  }
};

TEST_F(LawTraining, ShortTrainingLowersTheLoss) {
  const test::TinyGroundTruth truth = test::tiny_ground_truth(40);
  LawTrainer trainer(truth.config, truth.trajectory, short_training(8, 40));
  while (!trainer.finished()) {
    const EpochReport report = trainer.train_epoch();
    std::printf("epoch %lld: loss %.6g, gradient norms %.3g %.3g, %.2f s\n", (long long)report.epoch, report.loss,
                report.elastic_gradient_norm, report.plastic_gradient_norm, report.seconds);
  }
  const std::vector<double>& losses = trainer.losses();
  EXPECT_LT(losses.back(), 0.5 * losses.front());
}

std::vector<torch::Tensor> weights(const LawTrainer& trainer) {
  std::vector<torch::Tensor> copies;
  for (const torch::Tensor& p : trainer.laws().parameters()) copies.push_back(p.detach().clone());
  return copies;
}

TEST_F(LawTraining, ResumingFromACheckpointIsBitwiseUninterrupted) {
  const romp::test::ScratchFolder folder;
  const test::TinyGroundTruth truth = test::tiny_ground_truth(20);
  const TrainingOptions options = short_training(4, 20);

  LawTrainer uninterrupted(truth.config, truth.trajectory, options);
  while (!uninterrupted.finished()) uninterrupted.train_epoch();

  const std::string checkpoint = folder.file("law.h5.checkpoint");
  {
    LawTrainer first(truth.config, truth.trajectory, options);
    first.train_epoch();
    first.train_epoch();
    first.save_checkpoint(checkpoint);
  }
  LawTrainer resumed(truth.config, truth.trajectory, options);
  resumed.load_checkpoint(checkpoint);
  EXPECT_EQ(resumed.epochs_done(), 2);
  while (!resumed.finished()) resumed.train_epoch();

  EXPECT_EQ(resumed.losses(), uninterrupted.losses());
  const std::vector<torch::Tensor> expected = weights(uninterrupted), result = weights(resumed);
  ASSERT_EQ(result.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_TRUE(torch::equal(result[i], expected[i])) << "weight " << i;
}

TEST_F(LawTraining, RejectsACheckpointOfOtherOptions) {
  const romp::test::ScratchFolder folder;
  const test::TinyGroundTruth truth = test::tiny_ground_truth(10);
  const std::string checkpoint = folder.file("law.h5.checkpoint");
  LawTrainer(truth.config, truth.trajectory, short_training(3, 10)).save_checkpoint(checkpoint);
  LawTrainer other(truth.config, truth.trajectory, short_training(5, 10));
  EXPECT_THROW(other.load_checkpoint(checkpoint), Error);
  EXPECT_THROW(other.load_checkpoint(folder.write("garbage.checkpoint", "not an archive")), Error);
}

TEST_F(LawTraining, RejectsATrajectoryShorterThanTheRollout) {
  const test::TinyGroundTruth truth = test::tiny_ground_truth(5);
  EXPECT_THROW(LawTrainer(truth.config, truth.trajectory, short_training(1, 10)), Error);
}

}  // namespace
}  // namespace romp::nn::nclaw
