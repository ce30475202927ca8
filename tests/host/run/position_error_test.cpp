// The ROM paper's position error and the neural-law paper's mean MSE between two snapshot files:
// their values on known offsets, and the refusal to compare runs of different bodies or frame times.
#include "host/run/position_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "kernels/core/error.h"
#include "nn/io/snapshot_writer.h"
#include "tests/support/scratch_folder.h"

namespace romp::run {
namespace {

constexpr io::FieldMask kPositions = io::kFieldX;

// Two points; frame k holds X moved by offset × k along x.
std::string write_run(const test::ScratchFolder& folder, const std::string& name, const std::vector<float>& X,
                      float offset, const std::vector<double>& times) {
  io::SnapshotHeader header;
  header.X = X;
  const std::size_t n = X.size() / 3;
  header.mass.assign(n, 1.0f);
  header.volume0.assign(n, 1.0f);
  header.material.assign(n, 0);
  const std::string path = folder.file(name);
  io::SnapshotWriter writer(path, header, kPositions);
  for (std::size_t k = 0; k < times.size(); ++k) {
    io::FrameData frame;
    frame.time = times[k];
    frame.step = std::int64_t(k);
    frame.x = X;
    for (std::size_t p = 0; p < n; ++p) frame.x[p] += offset * float(k);
    writer.append_frame(frame);
  }
  writer.finish();
  return path;
}

const std::vector<float> kX = {0.0f, 3.0f, 4.0f, 0.0f, 0.0f, 0.0f};  // points (0, 4, 0) and (3, 0, 0): |x| = 4, 3

TEST(AccumulatedPositionError, IsTheRootOfTheSummedSquaredOffsetsOverTheSummedSquaredPositions) {
  const test::ScratchFolder folder;
  const std::string reference = write_run(folder, "reference.h5", kX, 0.0f, {0.0, 0.1});
  const std::string run = write_run(folder, "run.h5", kX, 0.5f, {0.0, 0.1});
  const PositionError error = compare_snapshots(run, reference);
  // Frame 0 matches; frame 1 is off by 0.5 at both points: √(2 · 0.25) / √(2 · 25) overall.
  ASSERT_EQ(error.frame_percent.size(), 2u);
  EXPECT_EQ(error.frame_percent[0], 0.0);
  EXPECT_NEAR(error.frame_percent[1], 100.0 * std::sqrt(0.5 / 25.0), 1e-9);
  EXPECT_NEAR(error.percent, 100.0 * std::sqrt(0.5 / 50.0), 1e-9);
  EXPECT_EQ(error.particles, 2);
  EXPECT_EQ(compare_snapshots(reference, reference).percent, 0.0);
}

TEST(MeanPositionMse, IsTheMeanOverFramesAfterTheFirstOfEachFramesMse) {
  const test::ScratchFolder folder;
  const std::string reference = write_run(folder, "reference.h5", kX, 0.0f, {0.0, 0.1, 0.2});
  const std::string run = write_run(folder, "run.h5", kX, 0.5f, {0.0, 0.1, 0.2});
  const PositionError error = compare_snapshots(run, reference);
  // Frame k is off by 0.5 k along x at both points: MSE over 2 points × 3 axes = 2 (0.5 k)² / 6.
  ASSERT_EQ(error.frame_mse.size(), 3u);
  EXPECT_EQ(error.frame_mse[0], 0.0);
  EXPECT_NEAR(error.frame_mse[1], 0.25 / 3.0, 1e-12);
  EXPECT_NEAR(error.frame_mse[2], 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(error.mean_mse, (0.25 / 3.0 + 1.0 / 3.0) / 2.0, 1e-12);
}

TEST(AccumulatedPositionError, RunsOfOtherBodiesOrFrameTimesAreNotCompared) {
  const test::ScratchFolder folder;
  const std::string reference = write_run(folder, "reference.h5", kX, 0.0f, {0.0, 0.1});
  const std::string moved = write_run(folder, "moved.h5", {0.0f, 3.0f, 4.0f, 0.0f, 0.0f, 1.0f}, 0.0f, {0.0, 0.1});
  const std::string later = write_run(folder, "later.h5", kX, 0.0f, {0.0, 0.2});
  const std::string shorter = write_run(folder, "shorter.h5", kX, 0.0f, {0.0});
  EXPECT_THROW(compare_snapshots(moved, reference), Error);
  EXPECT_THROW(compare_snapshots(later, reference), Error);
  EXPECT_THROW(compare_snapshots(shorter, reference), Error);
}

// --first-frames compares what both files hold of the first N frames: a run that stopped early against
// its reference, or the part of a longer run.
TEST(AccumulatedPositionError, FirstFramesComparesOnlyThose) {
  const test::ScratchFolder folder;
  const std::string reference = write_run(folder, "reference.h5", kX, 0.0f, {0.0, 0.1, 0.2});
  const std::string stopped = write_run(folder, "stopped.h5", kX, 0.5f, {0.0, 0.1});
  const PositionError error = compare_snapshots(stopped, reference, 2);
  ASSERT_EQ(error.frame_percent.size(), 2u);
  EXPECT_NEAR(error.percent, 100.0 * std::sqrt(0.5 / 50.0), 1e-9);  // as the two-frame runs above
  EXPECT_EQ(compare_snapshots(reference, reference, 1).frame_percent.size(), 1u);
  EXPECT_THROW(compare_snapshots(stopped, reference, 3), Error);  // the stopped run holds 2
}

}  // namespace
}  // namespace romp::run
