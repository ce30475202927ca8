// note_failed_points: a slot that names a point gets the point's particle and places copied beside it; an
// empty slot leaves its record as it was reset.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/mpm/failed_points.h"
#include "kernels/mpm/step.h"
#include "tests/support/test_exec.h"

namespace romp::mpm {
namespace {

TEST(NoteFailedPoints, CopiesThePointsTheirSlotsNameAndLeavesEmptySlotsAlone) {
  const Exec& exec = test::exec();
  const Backend backend = exec.backend;
  // Three points, 3 planes each: x = (i, 10 + i, 20 + i), X = x / 100.
  std::vector<float> x(9), X(9);
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < 3; ++a) {
      x[std::size_t(3 * a + i)] = float(10 * a + i);
      X[std::size_t(3 * a + i)] = float(10 * a + i) / 100.0f;
    }
  const auto x_device = DeviceBuffer<float>::from_host(backend, x),
             X_device = DeviceBuffer<float>::from_host(backend, X);
  const auto particles = DeviceBuffer<std::int32_t>::from_host(backend, {7, 42, 9});
  const Vec3Planes<const float> xs(x_device.data(), 3), Xs(X_device.data(), 3);
  // Slots: point 1 of a mapped source, point 2 of an unmapped one, point 0 of no particles, and none.
  auto slots = DeviceBuffer<std::int64_t>::from_host(backend, {1, 2, 0, kNoFailure});
  auto records = DeviceBuffer<std::int64_t>::from_host(backend, std::vector<std::int64_t>(16, kNoFailure));
  auto note = [&](int n, PointSource source) {
    return FailedPointNote{slots.span().subspan(n, 1), source, records.span().subspan(n * kFailedPointWords, 4)};
  };
  const FailedPointNotes notes = {note(0, {xs, Xs, particles.span()}), note(1, {xs, Xs, {}}),
                                  note(2, {xs, Xs, {}, /*particles=*/false}), note(3, {xs, Xs, particles.span()})};
  note_failed_points(exec, notes, 4);
  const std::vector<std::int64_t> host = records.to_host();
  auto record = [&host](int n) {
    return read_failed_point(Span<const std::int64_t>(host.data() + n * kFailedPointWords, kFailedPointWords));
  };
  EXPECT_EQ(record(0).particle, 42);
  EXPECT_EQ(record(0).x, Vec3<float>(1.0f, 11.0f, 21.0f));
  EXPECT_EQ(record(0).X, Vec3<float>(0.01f, 0.11f, 0.21f));
  EXPECT_EQ(record(1).particle, 2);
  EXPECT_EQ(record(1).x, Vec3<float>(2.0f, 12.0f, 22.0f));
  EXPECT_EQ(record(2).particle, -1);
  EXPECT_EQ(record(2).X, Vec3<float>(0.0f, 0.1f, 0.2f));
  EXPECT_EQ(host[3 * kFailedPointWords], kNoFailure);
  EXPECT_THROW(note_failed_points(exec, notes, kMostFailedPointNotes + 1), Error);
}

}  // namespace
}  // namespace romp::mpm
