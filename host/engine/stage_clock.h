// StageClock: times the stages of one substep in pipeline order on the simulation's backend (CUDA
// events on a GPU, a steady clock on the CPU), adding each stage's seconds to its entry of the table.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "kernels/core/device_timer.h"
#include "kernels/core/exec.h"

namespace romp {

class StageClock {
 public:
  // `seconds` lists the stages in the order they will run; it must outlive the clock.
  StageClock(const Exec& exec, std::vector<std::pair<std::string, double>>& seconds) : timer_(exec), seconds_(seconds) {}

  // Runs the next stage and adds its time to that stage's entry.
  template <class Stage>
  void operator()(Stage&& stage) {
    timer_.start();
    stage();
    seconds_[next_++].second += timer_.stop();
  }

 private:
  DeviceTimer timer_;
  std::vector<std::pair<std::string, double>>& seconds_;
  std::size_t next_ = 0;
};

}  // namespace romp
