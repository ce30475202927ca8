// EventTimeline: durations of consecutive intervals of the work queued on an Exec, read without waiting
// for the device at each interval (CUDA events on a GPU, a steady clock on the CPU).
//
// Why not a timer per interval. A timer that returns an interval's duration must wait for its end: on
// CUDA a blocking cudaEventSynchronize per stage, seven per reduced substep, each a round trip that also
// keeps the next stage's launches from queueing behind the current one. Here marks are only recorded;
// their times are read when the totals are asked for, or once per kCollectEvery marks, after the last
// of them has passed.
#pragma once

#include <chrono>
#include <cstddef>
#include <vector>

#include "kernels/core/exec.h"

struct CUevent_st;

namespace romp {

class EventTimeline {
 public:
  explicit EventTimeline(const Exec& exec);
  ~EventTimeline();
  EventTimeline(EventTimeline&& other) noexcept;
  EventTimeline& operator=(EventTimeline&& other) noexcept;
  EventTimeline(const EventTimeline&) = delete;
  EventTimeline& operator=(const EventTimeline&) = delete;

  // Starts a run of intervals at this point of exec's queue.
  void open();
  // Ends interval `interval` (an index into seconds()) here and starts the next one; after an open().
  void close(std::size_t interval);
  // Each interval's seconds summed over every close so far. Waits for the last mark on CUDA.
  const std::vector<double>& seconds();

  // Marks kept unread at most; an open() past them reads them first (one wait per this many marks).
  static constexpr std::size_t kCollectEvery = 1024;

 private:
  struct Mark {
    std::ptrdiff_t interval;                     // the interval it closes, or kOpens
    std::chrono::steady_clock::time_point time;  // CPU
  };
  static constexpr std::ptrdiff_t kOpens = -1;
  void record(std::ptrdiff_t interval);
  void collect();
  void release();

  Exec exec_;
  std::vector<Mark> marks_;          // unread, in queue order; marks_[i] uses events_[i] on CUDA
  std::vector<CUevent_st*> events_;  // created as marks need them, reused after each collect
  std::vector<double> seconds_;
};

}  // namespace romp
