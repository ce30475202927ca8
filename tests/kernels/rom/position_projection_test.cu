// The device Gauss–Newton of the position projection (ROM paper, Alg. 6) on the test backend: it finds the
// x̂ whose map reproduces the samples' positions from a guess away from it, extrapolates its guess from
// the history it keeps, counts projections that run out of iterations, reports a singular system, and
// reads nothing back for hyper-reduced sample counts (one decision per linearisation above them).
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/memory.h"
#include "kernels/rom/position_projection.h"
#include "kernels/rom/reduced_dynamics.h"
#include "tests/kernels/rom/reference_map.h"
#include "tests/support/test_exec.h"

namespace romp::rom {
namespace {

// The paper's network at r = 6, so that CUDA runs the fixed-shape evaluator inside the block.
constexpr int kLatent = 6, kHidden = 5, kWidth = 30;

Eigen::VectorXd true_xhat() {
  Eigen::VectorXd xhat(kLatent);
  xhat << 0.3, -0.2, 0.1, 0.25, -0.15, 0.05;
  return xhat;
}

// One projection's buffers on the test backend: m samples whose target positions are g(X; x̂_true).
struct Projection {
  ReferenceMap reference = random_map(kLatent, kHidden, kWidth, 41);
  UploadedMap<float> map;
  Index m;
  DeviceBuffer<float> X, target, model, dg, history, latent;
  DeviceBuffer<double> system;
  DeviceBuffer<GaussNewtonState> state;

  explicit Projection(Index samples) : m(samples) {
    const Exec& exec = test::exec();
    const Backend b = exec.backend;
    map = upload<float>(exec, reference, kHidden, kWidth);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<float> X_host(3 * m), target_host(3 * m);
    for (Index i = 0; i < m; ++i) {
      const Eigen::Vector3d point(-0.1 + 0.3 * unit(random), 0.2 + 0.4 * unit(random), 0.05 + 0.2 * unit(random));
      const Eigen::Vector3d x = reference.g(true_xhat(), point);
      for (int c = 0; c < 3; ++c) {
        X_host[c * m + i] = float(point(c));
        target_host[c * m + i] = float(x(c));
      }
    }
    X = DeviceBuffer<float>::from_host(b, X_host);
    target = DeviceBuffer<float>::from_host(b, target_host);
    model = DeviceBuffer<float>(b, 3 * m);
    dg = DeviceBuffer<float>(b, 3 * kLatent * m);
    system = DeviceBuffer<double>(b, kLatent * kLatent + kLatent + 1);
    history = DeviceBuffer<float>(b, 2 * kLatent);
    latent = DeviceBuffer<float>(b, 2 * kLatent + 1);
    state = DeviceBuffer<GaussNewtonState>(b, 1);
    state.fill_zero();
  }

  // Sets x̂ (the guess without extrapolation), v̂ = 0, status solved, and the history [x̂_{n−1} | x̂_n].
  void set(const std::vector<float>& xhat, const std::vector<float>& previous, const std::vector<float>& current) {
    std::vector<float> latent_host(xhat);
    latent_host.resize(2 * kLatent, 0.0f);
    latent_host.push_back(kLatentSolved);
    latent.copy_from_host(Span<const float>(latent_host.data(), latent_host.size()));
    std::vector<float> history_host(previous);
    history_host.insert(history_host.end(), current.begin(), current.end());
    history.copy_from_host(Span<const float>(history_host.data(), history_host.size()));
  }

  void run(bool extrapolate, GaussNewtonOptions options = {}) {
    project_positions(
        test::exec(), map.view, options, extrapolate,
        {Vec3Planes<const float>(X.data(), m), Vec3Planes<const float>(target.data(), m),
         Vec3Planes<float>(model.data(), m), dg.span(), system.span(), history.span(), latent.span(), state.span()});
  }
  std::vector<float> xhat() const {
    const std::vector<float> all = latent.to_host();
    return std::vector<float>(all.begin(), all.begin() + kLatent);
  }
  float status() const { return latent.to_host()[2 * kLatent]; }
  GaussNewtonState gauss_newton() const { return state.to_host()[0]; }
};

std::vector<float> offset_from_truth(double offset) {
  std::vector<float> xhat;
  for (int j = 0; j < kLatent; ++j) xhat.push_back(float(true_xhat()(j) + (j % 2 ? -offset : offset)));
  return xhat;
}

double distance_to_truth(const std::vector<float>& xhat) {
  double sum = 0.0;
  for (int j = 0; j < kLatent; ++j) sum += (xhat[j] - true_xhat()(j)) * (xhat[j] - true_xhat()(j));
  return std::sqrt(sum);
}

TEST(PositionProjection, FindsTheLatentStateThatReproducesThePositions) {
  Projection p(40);
  const std::vector<float> guess = offset_from_truth(0.05);  // 0.12 from the truth
  p.set(guess, guess, guess);
  p.run(/*extrapolate=*/false);
  EXPECT_EQ(p.gauss_newton().outcome, GaussNewtonState::kConverged);
  EXPECT_EQ(p.status(), kLatentSolved);
  // Float positions of magnitude 0.5 pin x̂ to about 1e-6 through a Jacobian of order 0.1.
  EXPECT_LT(distance_to_truth(p.xhat()), 1e-4) << "started at " << distance_to_truth(guess);
  EXPECT_EQ(p.gauss_newton().unconverged_total, 0);
  // The history advances to [x̂_n | x̂_{n+1}].
  const std::vector<float> history = p.history.to_host();
  for (int j = 0; j < kLatent; ++j) {
    EXPECT_EQ(history[j], guess[j]);
    EXPECT_EQ(history[kLatent + j], p.xhat()[j]);
  }
}

// At the solution already, positions exactly on the manifold: the cost is float rounding (1e-15 m²), and
// the model promises nothing above it: one linearisation, x̂ unchanged.
TEST(PositionProjection, StaysAtTheSolutionWhereItStartsThere) {
  Projection p(40);
  std::vector<float> truth;
  for (int j = 0; j < kLatent; ++j) truth.push_back(float(true_xhat()(j)));
  p.set(truth, truth, truth);
  p.run(/*extrapolate=*/false);
  EXPECT_EQ(p.gauss_newton().outcome, GaussNewtonState::kConverged);
  EXPECT_EQ(p.gauss_newton().linearisations_total, 1);
  EXPECT_EQ(p.xhat(), truth);
}

// Positions off the manifold (as a substep's trial positions are): once the linear model promises less
// than the cost's float resolution, the projection stops at the least-squares cost instead of wandering
// in the rounding (with the step criterion alone it took 22 linearisations on this input).
TEST(PositionProjection, StopsWhereTheCostIsResolvedNoFiner) {
  Projection p(20);
  std::vector<float> target = p.target.to_host();
  std::mt19937 random(3);
  std::normal_distribution<double> normal;
  for (float& value : target) value += float(1e-4 * normal(random));
  p.target.copy_from_host(Span<const float>(target.data(), Index(target.size())));
  // The cost at the true x̂: the least-squares cost can only be lower.
  const std::vector<float> X = p.X.to_host();
  double cost_at_truth = 0.0;
  for (Index i = 0; i < p.m; ++i) {
    const Eigen::Vector3d g = p.reference.g(true_xhat(), Eigen::Vector3d(X[i], X[p.m + i], X[2 * p.m + i]));
    for (int c = 0; c < 3; ++c) cost_at_truth += (target[c * p.m + i] - g(c)) * (target[c * p.m + i] - g(c));
  }
  const std::vector<float> guess = offset_from_truth(0.02);
  p.set(guess, guess, guess);
  p.run(/*extrapolate=*/false);
  const GaussNewtonState state = p.gauss_newton();
  EXPECT_EQ(state.outcome, GaussNewtonState::kConverged);
  EXPECT_LE(state.linearisations_total, 4);
  EXPECT_LT(state.cost, cost_at_truth);
}

TEST(PositionProjection, ExtrapolatesItsGuessFromTheLastTwoStates) {
  Projection p(40);
  // 2 x̂_n − x̂_{n−1} is the truth, x̂ (the other guess) far from it: one iteration that accepts the guess
  // and finds no step to take lands on the truth only from the extrapolated guess.
  const std::vector<float> previous = offset_from_truth(0.02), current = offset_from_truth(0.01);
  p.set(offset_from_truth(0.3), previous, current);
  p.run(/*extrapolate=*/true, {1, 1e-6});
  EXPECT_LT(distance_to_truth(p.xhat()), 1e-4);
}

TEST(PositionProjection, CountsProjectionsThatRunOutOfIterations) {
  Projection p(40);
  const std::vector<float> far = offset_from_truth(0.2);
  for (int run = 1; run <= 2; ++run) {
    p.set(far, far, far);
    p.run(/*extrapolate=*/false, {1, 1e-12});
    EXPECT_EQ(p.gauss_newton().outcome, GaussNewtonState::kUnconverged);
    EXPECT_EQ(p.gauss_newton().unconverged_total, run);  // never reset by a start
    // The one iteration still descended.
    EXPECT_LT(distance_to_truth(p.xhat()), distance_to_truth(far));
  }
}

TEST(PositionProjection, ASingularSystemIsReportedAndLeavesTheStateAsItWas) {
  Projection p(40);
  // Weights from x̂ to the first hidden layer all 0: g does not depend on x̂, A = 0.
  for (int unit = 0; unit < kWidth; ++unit)
    for (int j = 0; j < kLatent; ++j) p.reference.weights[0](unit, j) = 0.0;
  p.map = upload<float>(test::exec(), p.reference, kHidden, kWidth);
  const std::vector<float> guess = offset_from_truth(0.05);
  p.set(guess, guess, guess);
  p.run(/*extrapolate=*/false);
  EXPECT_EQ(p.status(), kLatentSingular);
  EXPECT_EQ(p.xhat(), guess);
}

// Hyper-reduced sample counts read nothing back; above kOneBlockSamples each decision comes back once,
// and the result is the same projection.
TEST(PositionProjection, ReadsBackNothingForHyperReducedSampleCounts) {
  const std::vector<float> guess = offset_from_truth(0.05);
  auto downloads = [&](Projection& p) {
    p.set(guess, guess, guess);
    const memory::Traffic before = memory::traffic();
    p.run(/*extrapolate=*/false);
    return memory::traffic().downloads - before.downloads;
  };
  Projection few(60);
  EXPECT_EQ(downloads(few), 0);
  Projection many(kOneBlockSamples + 1);
  const std::int64_t linearisations = downloads(many);
  EXPECT_GE(linearisations, 2);
  EXPECT_LE(linearisations, 1 + 10 * (kLineSearchHalvings + 1));
  EXPECT_LT(distance_to_truth(many.xhat()), 1e-4);
}

TEST(PositionProjection, RejectsBuffersOfTheWrongSize) {
  Projection p(40);
  p.history = DeviceBuffer<float>(test::exec().backend, kLatent);  // x̂_n only
  EXPECT_THROW(p.run(false), Error);
}

}  // namespace
}  // namespace romp::rom
