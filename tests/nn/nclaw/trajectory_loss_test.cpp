// backpropagate_trajectory_loss: its value and the gradients it leaves on the laws' weights against the
// loss written out by hand, segment by segment, with and without the velocity penalty.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <vector>

#include "kernels/core/error.h"
#include "nn/nclaw/neural_laws.h"
#include "nn/nclaw/trajectory_loss.h"
#include "tests/nn/nclaw/tiny_trajectory.h"

namespace romp::nn::nclaw {
namespace {

constexpr int64_t kSteps = 40, kPeriod = 15;  // segments of 15, 15 and 10 substeps; the cube lands in the first
constexpr double kScale = 1e4;

class TrajectoryLoss : public ::testing::Test {
 protected:
  void SetUp() override {
    omp_set_num_threads(1);  // one P2G summation order: the two losses below see the same rollouts
    torch::set_num_threads(1);
  }
  const test::TinyGroundTruth truth = test::tiny_ground_truth(kSteps);
  const diffmpm::DiffMpm sim{truth.config, truth.trajectory.mass, truth.trajectory.volume};
  const NeuralLaws laws = seeded_laws(3, torch::TensorOptions().dtype(torch::kFloat32));

  // The gradient of every weight, then cleared.
  std::vector<torch::Tensor> take_gradients() const {
    std::vector<torch::Tensor> gradients;
    for (torch::Tensor p : laws.parameters()) {
      gradients.push_back(p.grad().clone());
      p.mutable_grad() = torch::Tensor();
    }
    return gradients;
  }

  // Each segment restarts from the truth; Σ over substeps of scale · (MSE(x) + w · MSE(v)).
  double loss_by_hand(double velocity_weight) const {
    double total = 0.0;
    for (int64_t start = 0; start < kSteps; start += kPeriod) {
      const int64_t steps = std::min(kPeriod, kSteps - start);
      const diffmpm::Rollout r = diffmpm::rollout(sim, truth.trajectory.state(start), laws.constitutive(), {steps, 0});
      torch::Tensor loss = torch::zeros({}, torch::kFloat32);
      for (int64_t s = 0; s < steps; ++s) {
        loss = loss + (r.positions[s] - truth.trajectory.x[start + 1 + s]).square().mean();
        loss = loss + velocity_weight * (r.velocities[s] - truth.trajectory.v[start + 1 + s]).square().mean();
      }
      loss = kScale * loss;
      loss.backward();
      total += loss.item<double>();
    }
    return total;
  }
};

void expect_same_gradients(const std::vector<torch::Tensor>& a, const std::vector<torch::Tensor>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i)
    EXPECT_TRUE(torch::allclose(a[i], b[i], 1e-4, 1e-6 * b[i].abs().max().item<double>())) << "weight tensor " << i;
}

TEST_F(TrajectoryLoss, MatchesTheLossWrittenOutSegmentBySegment) {
  for (double velocity_weight : {0.0, 0.02}) {
    SCOPED_TRACE(velocity_weight);
    const double value = backpropagate_trajectory_loss(sim, truth.trajectory, laws.constitutive(),
                                                       {kSteps, kPeriod, kScale, 0, velocity_weight})
                             .value;
    const std::vector<torch::Tensor> gradients = take_gradients();
    const double expected = loss_by_hand(velocity_weight);
    EXPECT_NEAR(value, expected, 1e-5 * expected);
    expect_same_gradients(gradients, take_gradients());
  }
}

TEST_F(TrajectoryLoss, VelocityPenaltyAddsToThePositionLoss) {
  const TrajectoryLossOptions positions_only{kSteps, kPeriod, kScale, 0, 0.0};
  TrajectoryLossOptions with_velocities = positions_only;
  with_velocities.velocity_weight = 0.02;
  const double x_only = backpropagate_trajectory_loss(sim, truth.trajectory, laws.constitutive(), positions_only).value;
  take_gradients();
  const double both = backpropagate_trajectory_loss(sim, truth.trajectory, laws.constitutive(), with_velocities).value;
  take_gradients();
  std::printf("loss: positions %.6g, with velocities %.6g\n", x_only, both);
  // The untrained laws miss the truth's velocities by far more than 1e-3 m/s.
  EXPECT_GT(both - x_only, kScale * 0.02 * 1e-6 * double(kSteps));
}

TEST_F(TrajectoryLoss, RejectsANegativeVelocityWeight) {
  EXPECT_THROW(
      backpropagate_trajectory_loss(sim, truth.trajectory, laws.constitutive(), {kSteps, kPeriod, kScale, 0, -1.0}),
      Error);
}

}  // namespace
}  // namespace romp::nn::nclaw
