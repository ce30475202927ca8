// The ROM paper's accuracy measure (Sec. 5): the accumulated position error of a run against a
// reference run of the same scene,
//   error (%) = 100 √(Σ_{n,p} ‖x_run − x_ref‖²) / √(Σ_{n,p} ‖x_ref‖²),
// summed over every frame n and material point p, and the same ratio per frame. Beside it, the
// neural-law paper's metric (Ma et al. 2023, Sec. 4.1): the mean over frames after the first of the
// position MSE (m², over material points and axes); on snapshots written every 5th substep, as the
// scenes of scenes/nclaw/generalization are, that is the paper's "average MSE every 5 frames".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace romp::run {

struct PositionError {
  double percent = 0.0;               // over all frames
  std::vector<double> frame_percent;  // per frame
  std::vector<double> frame_times;    // s
  std::vector<double> frame_mse;      // per frame: mean over points and axes of (x_run − x_ref)², m²
  double mean_mse = 0.0;              // over every frame but the first (both start from the same state)
  std::int64_t particles = 0;
};

// Sums the error frame by frame, for runs held in memory (romp-bench) or read from files.
class PositionErrorAccumulator {
 public:
  // One frame's positions (3 planes of the same material points, same order) at time t.
  void add_frame(double t, const std::vector<float>& x, const std::vector<float>& reference);
  PositionError result() const;

 private:
  PositionError partial_;
  double error_sum_ = 0.0, reference_sum_ = 0.0;
};

// Compares two snapshot files frame by frame. They must hold the same material points (count and
// reference positions) and the same frame times; throws romp::Error naming both files otherwise.
// `first_frames` > 0 compares frames 0 .. first_frames − 1 only (both files must hold them), e.g. what
// a run that stopped early wrote (RUN.h5.partial) or the part of a run before it diverged.
PositionError compare_snapshots(const std::string& run, const std::string& reference, std::int64_t first_frames = 0);

}  // namespace romp::run
