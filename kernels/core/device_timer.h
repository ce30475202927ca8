// DeviceTimer: elapsed time of work queued on an Exec (CUDA events on a GPU, a steady clock on the CPU).
#pragma once

#include <chrono>

#include "kernels/core/exec.h"

struct CUevent_st;

namespace romp {

class DeviceTimer {
 public:
  explicit DeviceTimer(const Exec& exec);
  ~DeviceTimer();
  DeviceTimer(const DeviceTimer&) = delete;
  DeviceTimer& operator=(const DeviceTimer&) = delete;

  void start();
  // Waits for the work queued since start() and returns its duration in seconds.
  double stop();

 private:
  Exec exec_;
  std::chrono::steady_clock::time_point host_start_;
  CUevent_st* begin_ = nullptr;
  CUevent_st* end_ = nullptr;
};

}  // namespace romp
