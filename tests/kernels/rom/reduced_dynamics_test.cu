// The velocity projection where its data is (ROM paper, Alg. 6–7): normal_equations of random Jacobians
// and velocities, then advance_latent, against a least-squares solve by Eigen on the host; a singular
// system, which must leave x̂ and v̂ as they were and say so; and the domain check of decoded points.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <limits>
#include <random>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/rom/reduced_dynamics.h"
#include "tests/support/test_exec.h"

namespace romp::rom {
namespace {

constexpr int kLatent = 5;
constexpr Index kPoints = 40;
constexpr float kDt = 1e-3f;

struct Projection {
  std::vector<float> J, v, latent;  // 3 r planes of m; 3 planes of m; [x̂ | v̂ | status]
};

// Runs normal_equations and advance_latent on the test backend; returns the latent state after.
std::vector<float> advance_on_device(const Projection& p) {
  const Backend backend = test::exec().backend;
  const auto J = DeviceBuffer<float>::from_host(backend, p.J);
  const auto v = DeviceBuffer<float>::from_host(backend, p.v);
  auto latent = DeviceBuffer<float>::from_host(backend, p.latent);
  DeviceBuffer<double> system(backend, kLatent * kLatent + kLatent + 1);
  normal_equations(test::exec(), kLatent, J.span(), Vec3Planes<const float>(v.data(), kPoints), {}, system.span());
  advance_latent(test::exec(), kLatent, system.span(), kDt, latent.span());
  return latent.to_host();
}

Projection random_projection() {
  std::mt19937 random(11);
  std::normal_distribution<float> normal;
  Projection p;
  for (Index i = 0; i < 3 * kLatent * kPoints; ++i) p.J.push_back(normal(random));
  for (Index i = 0; i < 3 * kPoints; ++i) p.v.push_back(normal(random));
  for (int j = 0; j < 2 * kLatent; ++j) p.latent.push_back(normal(random));
  p.latent.push_back(-1.0f);  // status: to be overwritten
  return p;
}

TEST(AdvanceLatent, SolvesTheVelocityProjectionAndStepsThePositions) {
  const Projection p = random_projection();
  // v̂ = argmin Σ_p ‖J_p v̂ − v_p‖², rows (o, p) of the stacked J.
  Eigen::MatrixXd J(3 * kPoints, kLatent);
  Eigen::VectorXd v(3 * kPoints);
  for (int o = 0; o < 3; ++o)
    for (Index q = 0; q < kPoints; ++q) {
      v(o * kPoints + q) = p.v[o * kPoints + q];
      for (int j = 0; j < kLatent; ++j) J(o * kPoints + q, j) = p.J[(o * kLatent + j) * kPoints + q];
    }
  const Eigen::VectorXd vhat = J.colPivHouseholderQr().solve(v);

  const std::vector<float> latent = advance_on_device(p);
  EXPECT_EQ(latent[2 * kLatent], kLatentSolved);
  for (int j = 0; j < kLatent; ++j) {
    EXPECT_NEAR(latent[kLatent + j], vhat(j), 1e-5 * (1.0 + std::abs(vhat(j)))) << "v̂ " << j;
    EXPECT_NEAR(latent[j], p.latent[j] + kDt * vhat(j), 1e-6 * (1.0 + std::abs(p.latent[j]))) << "x̂ " << j;
  }
}

TEST(AdvanceLatent, ReportsASingularSystemAndKeepsTheState) {
  Projection p = random_projection();
  std::fill(p.J.begin(), p.J.end(), 0.0f);  // the points do not move with x̂: A = 0
  const std::vector<float> latent = advance_on_device(p);
  EXPECT_EQ(latent[2 * kLatent], kLatentSingular);
  for (int j = 0; j < 2 * kLatent; ++j) EXPECT_EQ(latent[j], p.latent[j]) << j;
}

TEST(AdvanceLatent, RejectsALatentStateOfTheWrongSize) {
  DeviceBuffer<double> system(test::exec().backend, kLatent * kLatent + kLatent + 1);
  DeviceBuffer<float> latent(test::exec().backend, 2 * kLatent);  // no status slot
  EXPECT_THROW(advance_latent(test::exec(), kLatent, system.span(), kDt, latent.span()), Error);
}

// Points outside the band the full-order step keeps particles in are moved back into it, as that step would
// (a NaN coordinate to the low bound), and the lowest such index is noted; points inside stay put.
TEST(KeepPointsInside, MovesPointsOutsideIntoTheBandAndNotesTheFirst) {
  mpm::Domain domain;
  domain.cells[0] = domain.cells[1] = domain.cells[2] = 10;
  const float dx = 0.1f, low = domain.low_bound(dx), high = domain.high_bound(1, dx);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Point 0 inside, 1 on the bounds, 2 past the high bound in y, 3 NaN in z, 4 below in x.
  const std::vector<float> planes = {0.5f, low,  0.5f, 0.5f, -3.0f,  // x
                                     0.5f, high, 2.0f, 0.5f, 0.5f,   // y
                                     0.5f, low,  0.5f, nan,  0.5f};  // z
  const Backend backend = test::exec().backend;
  auto x = DeviceBuffer<float>::from_host(backend, planes);
  auto first = DeviceBuffer<std::int64_t>::from_host(backend, {kNoPointOutside});
  keep_points_inside(test::exec(), Vec3Planes<float>(x.data(), 5), domain, dx, first.span());
  EXPECT_EQ(first.to_host()[0], 2);
  std::vector<float> expected = planes;
  expected[5 + 2] = high;
  expected[10 + 3] = low;
  expected[0 + 4] = low;
  EXPECT_EQ(x.to_host(), expected);

  // Nothing outside: the slot keeps its sentinel.
  auto inside = DeviceBuffer<float>::from_host(backend, {0.5f, 0.5f, 0.5f});
  auto none = DeviceBuffer<std::int64_t>::from_host(backend, {kNoPointOutside});
  keep_points_inside(test::exec(), Vec3Planes<float>(inside.data(), 1), domain, dx, none.span());
  EXPECT_EQ(none.to_host()[0], kNoPointOutside);
}

}  // namespace
}  // namespace romp::rom
