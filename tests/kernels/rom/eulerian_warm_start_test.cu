// Warm starts of the Eulerian inversion: a point finds its place among the last build's points (a binary search
// over (cell, sub)) and, where that point was used, starts from its solution moved back by how x̂ moved.
#include "kernels/rom/eulerian_warm_start.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <type_traits>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/math/mat3.h"
#include "tests/support/test_exec.h"

namespace romp::rom {
namespace {

// Three points last time, at places (5, 0), (5, 3) and (9, 1); the second was dropped outside the body.
struct Last {
  std::vector<std::uint64_t> cell{5, 5, 9};
  std::vector<std::int32_t> sub{0, 3, 1}, status{kQuadratureUsed, kQuadratureOutside, kQuadratureUsed};
  // X, v and F of the 3 points as planes: F = 2 I, I and I with F(0, 2) = 0.5.
  std::vector<float> X{0.1f, 0.3f, 0.5f, 1.1f, 1.3f, 1.5f, 2.1f, 2.3f, 2.5f};
  std::vector<float> v{1.0f, 0.0f, 0.0f, 0.0f, 0.0f, 2.0f, 0.0f, 0.0f, -1.0f};
  std::vector<float> F{2.0f, 1.0f, 1.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.5f,   // row 0
                       0.0f, 0.0f, 0.0f, 2.0f, 1.0f, 1.0f, 0.0f, 0.0f, 0.0f,   // row 1
                       0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 2.0f, 1.0f, 1.0f};  // row 2
  std::vector<float> xhat{0.0f, 1.0f}, vhat{0.0f, 2.0f};
};

TEST(EulerianWarmStart, PointsAtAUsedPlaceStartFromItsSolutionMovedBackAlongV) {
  const Exec& exec = test::exec();
  const Last host;
  const auto upload = [&](const auto& values) {
    return DeviceBuffer<std::decay_t<decltype(values[0])>>::from_host(exec.backend, values, exec.stream);
  };
  const auto cell = upload(host.cell);
  const auto sub = upload(host.sub);
  const auto status = upload(host.status);
  const auto X = upload(host.X), v = upload(host.v), F = upload(host.F), xhat = upload(host.xhat),
             vhat = upload(host.vhat);
  const Inversions last{cell.span(),
                        sub.span(),
                        status.span(),
                        Vec3Planes<const float>(X.data(), 3),
                        Vec3Planes<const float>(v.data(), 3),
                        Mat3Planes<const float>(F.data(), 3),
                        xhat.span(),
                        vhat.span()};
  // Now: x̂ moved by 0.01 v̂ (α = 0.01). Points at (5, 0) (used), (5, 3) (outside), (7, 0) (new), (9, 1) (used).
  const std::vector<float> xhat_now{0.0f, 1.02f};
  const auto now = upload(xhat_now);
  const auto now_cell = upload(std::vector<std::uint64_t>{5, 5, 7, 9});
  const auto now_sub = upload(std::vector<std::int32_t>{0, 3, 0, 1});
  std::vector<float> guesses(3 * 4, -7.0f), jacobians(9 * 4, -7.0f);
  auto X_guess = upload(guesses);
  auto F_guess = upload(jacobians);
  DeviceBuffer<QuadratureTally> tally(exec.backend, 1);
  tally.fill_zero(exec.stream);
  warm_start_inversions(exec, last, now.span(), now_cell.span(), now_sub.span(), Vec3Planes<float>(X_guess.data(), 4),
                        Mat3Planes<float>(F_guess.data(), 4), tally.span());
  const std::vector<float> X_out = X_guess.to_host(exec.stream), F_out = F_guess.to_host(exec.stream);
  EXPECT_EQ(tally.to_host(exec.stream)[0].warm_starts, 2);
  const auto X_of = [&](int i) { return Vec3<float>(X_out[i], X_out[4 + i], X_out[8 + i]); };
  // (5, 0): X − α F⁻¹ v = (0.1, 1.1, 2.1) − 0.01 (0.5, 0, 0).
  EXPECT_NEAR(X_of(0)[0], 0.1f - 0.005f, 1e-6f);
  EXPECT_NEAR(X_of(0)[1], 1.1f, 1e-6f);
  EXPECT_NEAR(X_of(0)[2], 2.1f, 1e-6f);
  EXPECT_FLOAT_EQ(F_out[0], 2.0f);  // F(0, 0) of point 0: the last solution's
  // (9, 1): F = I + 0.5 e₀e₂ᵀ, v = (0, 2, −1): F⁻¹ v = (0.5, 2, −1).
  EXPECT_NEAR(X_of(3)[0], 0.5f - 0.01f * 0.5f, 1e-6f);
  EXPECT_NEAR(X_of(3)[1], 1.5f - 0.01f * 2.0f, 1e-6f);
  EXPECT_NEAR(X_of(3)[2], 2.5f + 0.01f, 1e-6f);
  // The outside point's and the new point's guesses are left alone.
  for (int i : {1, 2}) {
    for (int a = 0; a < 3; ++a) EXPECT_EQ(X_of(i)[a], -7.0f) << i;
    for (int e = 0; e < 9; ++e) EXPECT_EQ(F_out[e * 4 + i], -7.0f) << i;
  }
}

}  // namespace
}  // namespace romp::rom
