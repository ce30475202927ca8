// ProgressBar: a one-line report of a run's progress on the terminal (bar, frame, simulated time,
// elapsed time and ETA), or a log line every tenth of the run when stderr is not a terminal.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace romp::run {

class ProgressBar {
 public:
  // `first_frame` is where a resumed run starts; the ETA counts only the frames this process runs.
  ProgressBar(std::int64_t first_frame, std::int64_t last_frame, double end_time);

  void update(std::int64_t frame, double simulated_time);
  // Ends the line on a terminal.
  void finish();

  // The text of one update, for tests: "[#####-----]  50% frame 5/10  t = 0.250/0.500 s  1.2 s, ETA 1.2 s".
  static std::string line(std::int64_t frame, std::int64_t first_frame, std::int64_t last_frame, double simulated_time,
                          double end_time, double elapsed_seconds);

 private:
  std::int64_t first_frame_, last_frame_;
  double end_time_;
  bool terminal_;
  int last_logged_tenth_ = -1;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace romp::run
