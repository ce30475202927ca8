// Frame-by-frame comparison of two snapshot files by the ROM paper's position error.
#include "host/run/position_error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "kernels/core/error.h"
#include "nn/io/snapshot_reader.h"
#include "nn/io/unusable_file_error.h"

namespace romp::run {
namespace {

// Frame times this close (relative to the larger) are the same frame.
constexpr double kTimeTolerance = 1e-9;

}  // namespace

void PositionErrorAccumulator::add_frame(double t, const std::vector<float>& x, const std::vector<float>& reference) {
  ROMP_CHECK(x.size() == reference.size() && x.size() % 3 == 0,
             fmt::format("positions of {} and {} values cannot be compared", x.size(), reference.size()));
  double frame_error = 0.0, frame_reference = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double d = double(x[i]) - double(reference[i]);
    frame_error += d * d;
    frame_reference += double(reference[i]) * double(reference[i]);
  }
  error_sum_ += frame_error;
  reference_sum_ += frame_reference;
  partial_.particles = std::int64_t(x.size() / 3);
  partial_.frame_times.push_back(t);
  partial_.frame_percent.push_back(100.0 * std::sqrt(frame_error / frame_reference));
  partial_.frame_mse.push_back(frame_error / double(x.size()));
}

PositionError PositionErrorAccumulator::result() const {
  PositionError result = partial_;
  result.percent = 100.0 * std::sqrt(error_sum_ / reference_sum_);
  const std::size_t frames = result.frame_mse.size();
  if (frames > 1) {
    for (std::size_t k = 1; k < frames; ++k) result.mean_mse += result.frame_mse[k];
    result.mean_mse /= double(frames - 1);
  }
  return result;
}

PositionError compare_snapshots(const std::string& run, const std::string& reference, std::int64_t first_frames) {
  const io::SnapshotReader a(run), b(reference);
  const std::string pair = fmt::format("{} against {}", run, reference);
  if (a.particle_count() != b.particle_count())
    throw io::UnusableFileError(
        fmt::format("{}: {} material points against {}; compare runs of the same scene and sampling", pair,
                    a.particle_count(), b.particle_count()));
  if (a.header().X != b.header().X)
    throw io::UnusableFileError(
        fmt::format("{}: the material points' reference positions differ; compare runs of the same scene "
                    "and sampling",
                    pair));
  if (first_frames <= 0 && a.frame_count() != b.frame_count())
    throw io::UnusableFileError(fmt::format("{}: {} frames against {} (--first-frames N compares the first N)", pair,
                                            a.frame_count(), b.frame_count()));
  if (first_frames > std::min(a.frame_count(), b.frame_count()))
    throw io::UnusableFileError(fmt::format("{}: the first {} frames were asked for; the files hold {} and {}", pair,
                                            first_frames, a.frame_count(), b.frame_count()));
  const std::int64_t frames = first_frames > 0 ? first_frames : a.frame_count();

  PositionErrorAccumulator accumulator;
  for (std::int64_t frame = 0; frame < frames; ++frame) {
    const double t = a.frame_time(frame), t_reference = b.frame_time(frame);
    if (std::fabs(t - t_reference) > kTimeTolerance * std::fmax(1.0, std::fabs(t_reference)))
      throw io::UnusableFileError(
          fmt::format("{}: frame {} is at t = {} s against t = {} s", pair, frame, t, t_reference));
    accumulator.add_frame(t, a.read_frame(frame).x, b.read_frame(frame).x);
  }
  return accumulator.result();
}

}  // namespace romp::run
