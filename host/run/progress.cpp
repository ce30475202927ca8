// ProgressBar.
#include "host/run/progress.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdio>

namespace romp::run {
namespace {

constexpr int kBarWidth = 24;

std::string duration(double seconds) {
  if (seconds < 60.0) return fmt::format("{:.1f} s", seconds);
  if (seconds < 3600.0) return fmt::format("{}m{:02}s", int(seconds / 60.0), int(seconds) % 60);
  return fmt::format("{}h{:02}m", int(seconds / 3600.0), int(seconds / 60.0) % 60);
}

}  // namespace

ProgressBar::ProgressBar(std::int64_t first_frame, std::int64_t last_frame, double end_time)
    : first_frame_(first_frame),
      last_frame_(last_frame),
      end_time_(end_time),
      terminal_(isatty(fileno(stderr)) != 0),
      start_(std::chrono::steady_clock::now()) {}

std::string ProgressBar::line(std::int64_t frame, std::int64_t first_frame, std::int64_t last_frame,
                              double simulated_time, double end_time, double elapsed_seconds) {
  const double done = last_frame > 0 ? double(frame) / double(last_frame) : 1.0;
  const int filled = int(done * kBarWidth + 0.5);
  const std::int64_t run = frame - first_frame, remaining = last_frame - frame;
  const std::string eta = run > 0 ? duration(elapsed_seconds / double(run) * double(remaining)) : "?";
  return fmt::format("[{}{}] {:3.0f}% frame {}/{}  t = {:.3f}/{:.3f} s  {}, ETA {}", std::string(filled, '#'),
                     std::string(kBarWidth - filled, '-'), 100.0 * done, frame, last_frame, simulated_time, end_time,
                     duration(elapsed_seconds), eta);
}

void ProgressBar::update(std::int64_t frame, double simulated_time) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::string text = line(frame, first_frame_, last_frame_, simulated_time, end_time_, elapsed);
  if (terminal_) {
    std::fprintf(stderr, "\r%s", text.c_str());
    std::fflush(stderr);
    return;
  }
  const int tenth = last_frame_ > 0 ? int(10 * frame / last_frame_) : 10;
  if (tenth != last_logged_tenth_) {
    last_logged_tenth_ = tenth;
    spdlog::info("{}", text);
  }
}

void ProgressBar::finish() {
  if (terminal_) std::fprintf(stderr, "\n");
}

}  // namespace romp::run
