// position_error: zero for the law that made the trajectory, the offset's square for a shifted one.
#include "nn/nclaw/evaluation.h"

#include <gtest/gtest.h>
#include <omp.h>

#include "kernels/core/error.h"
#include "nn/nclaw/fixed_corotated.h"
#include "tests/nn/nclaw/tiny_trajectory.h"

namespace romp::nn::nclaw {
namespace {

TEST(PositionError, IsTheMeanSquaredOffsetOfEveryFifthFrame) {
  // One thread: the rollout then repeats the ground truth's float sums exactly.
  omp_set_num_threads(1);
  torch::set_num_threads(1);
  const test::TinyGroundTruth truth = test::tiny_ground_truth(20);
  const diffmpm::DiffMpm sim(truth.config, truth.trajectory.mass, truth.trajectory.volume);
  const torch::Tensor youngs = torch::tensor(1e4f), poisson = torch::tensor(0.3f);
  const diffmpm::ConstitutiveLaws law{
      [&](const torch::Tensor& F) { return fixed_corotated_stress(F, youngs, poisson); }, {}, {}};
  EXPECT_EQ(position_error(sim, truth.trajectory, law, 20), 0.0);

  // Frames 5, 10, 15, 20 moved by 0.01 m along x: MSE over three axes (0.01² / 3); other frames
  // and the first four substeps do not count.
  Trajectory shifted = truth.trajectory;
  shifted.x = shifted.x.clone();
  shifted.x.slice(0, 5, 21, 5).select(1, 0).add_(0.01f);
  EXPECT_NEAR(position_error(sim, shifted, law, 20), 1e-4 / 3.0, 1e-9);
  EXPECT_THROW(position_error(sim, truth.trajectory, law, 21), Error);
}

}  // namespace
}  // namespace romp::nn::nclaw
