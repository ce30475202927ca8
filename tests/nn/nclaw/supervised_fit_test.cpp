// Supervised oracle: the neural laws fitted to constitutive pairs taken from a trajectory.
#include "nn/nclaw/supervised_fit.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "nn/nclaw/features.h"
#include "nn/nclaw/fixed_corotated.h"
#include "tests/nn/nclaw/tiny_trajectory.h"

namespace romp::nn::nclaw {
namespace {

// The trial F of the substep from frame k to k + 1 is (I + dt C_{k+1}) F_k: for the purely elastic
// jelly, the projection is the identity and the pairs agree exactly up to rounding.
TEST(SupervisedFit, PlasticPairsOfAnElasticTrajectoryAreUnchangedF) {
  const test::TinyGroundTruth truth = test::tiny_ground_truth(10);
  ConstitutivePairs pairs;
  add_plastic_pairs(truth.trajectory, truth.config.fixed_dt, pairs);
  ASSERT_EQ(pairs.F_trial.sizes(), (std::vector<int64_t>{9, 10 * truth.trajectory.particle_count()}));
  EXPECT_LE((pairs.F_trial - pairs.F_projected).abs().max().item<double>(), 1e-6);
}

// The elastic law learns the jelly's stress at the deformations of its own trajectory (every 4th frame).
TEST(SupervisedFit, ElasticLawLearnsTheStressOfItsPairs) {
  const test::TinyGroundTruth truth = test::tiny_ground_truth(40);
  ConstitutivePairs pairs;
  pairs.F = truth.trajectory.F.slice(0, 0, c10::nullopt, 4).permute({1, 0, 2}).reshape({9, -1}).contiguous();
  pairs.P = fixed_corotated_stress(pairs.F, torch::tensor(1e4f), torch::tensor(0.3f)).detach();
  NeuralLaws laws = seeded_laws(3, torch::kFloat32);
  SupervisedOptions options;
  options.epochs = 100;
  const SupervisedLosses losses = fit_supervised(laws, pairs, options);
  std::printf("relative stress error: %.3g at the start, %.3g after %lld epochs\n", losses.elastic.front(),
              losses.elastic.back(), (long long)options.epochs);
  EXPECT_LT(losses.elastic.back(), 0.01 * losses.elastic.front());
}

// A relaxation toward the rest shape, F_new = F − α R (S − 1) with F = R S, is a plastic law of the
// network's form (T = 1 − S): the plastic law learns it from random trial F.
TEST(SupervisedFit, PlasticLawLearnsARelaxation) {
  torch::manual_seed(4);
  const int64_t m = 512;
  ConstitutivePairs pairs;
  pairs.F_trial = (torch::eye(3).reshape({9, 1}) + 0.2 * torch::randn({9, m})).contiguous();
  const torch::Tensor F = planes_to_matrices(pairs.F_trial);
  const torch::Tensor R = stretch_and_rotation(pairs.F_trial).R;
  pairs.F_projected = matrices_to_planes(F - kPlasticStep * (F - R)).detach();
  NeuralLaws laws = seeded_laws(5, torch::kFloat32);
  SupervisedOptions options;
  options.epochs = 100;
  const SupervisedLosses losses = fit_supervised(laws, pairs, options);
  std::printf("relative plastic error: %.3g at the start, %.3g after %lld epochs\n", losses.plastic.front(),
              losses.plastic.back(), (long long)options.epochs);
  EXPECT_TRUE(losses.elastic.empty());
  EXPECT_LT(losses.plastic.back(), 0.01 * losses.plastic.front());
}

}  // namespace
}  // namespace romp::nn::nclaw
