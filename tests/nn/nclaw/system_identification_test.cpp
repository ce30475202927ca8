// System identification: E and ν of fixed corotated elasticity recovered from a trajectory.
#include "nn/nclaw/system_identification.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <cstdio>

#include "tests/nn/nclaw/tiny_trajectory.h"

namespace romp::nn::nclaw {
namespace {

// The tiny jelly (E = 1e4 Pa, ν = 0.3) from a 3x too stiff, too compressible start, with full
// 40-substep rollouts (no restarts).
TEST(SystemIdentification, RecoversYoungsModulusAndPoissonsRatio) {
  omp_set_num_threads(1);
  torch::set_num_threads(1);
  const test::TinyGroundTruth truth = test::tiny_ground_truth(40);
  SystemIdentificationOptions options;
  options.epochs = 80;
  options.steps = 40;
  options.teacher_forcing_first = 40;
  options.teacher_forcing_last = 40;
  options.initial_youngs = 3e4;
  options.initial_poisson = 0.2;
  SystemIdentification identification(truth.config, truth.trajectory, options);
  while (!identification.finished()) {
    const double loss = identification.train_epoch();
    std::printf("epoch %lld: loss %.4g, E = %.5g Pa, nu = %.4f\n", (long long)identification.epochs_done(), loss,
                identification.youngs(), identification.poisson());
  }
  EXPECT_NEAR(identification.youngs(), 1e4, 0.02 * 1e4);
  EXPECT_NEAR(identification.poisson(), 0.3, 0.01);
}

}  // namespace
}  // namespace romp::nn::nclaw
