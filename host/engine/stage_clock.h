// StageClock: times the stages of one substep in pipeline order on the simulation's timeline (CUDA
// events on a GPU, a steady clock on the CPU; kernels/core/event_timeline.h), each stage's time going
// to its interval: the index of its entry in the simulation's stage table. Nothing waits for the device.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "kernels/core/event_timeline.h"

namespace romp::engine {

class StageClock {
 public:
  explicit StageClock(EventTimeline& timeline) : timeline_(timeline) { timeline_.open(); }

  // Runs the next stage and marks its end.
  template <class Stage>
  void operator()(Stage&& stage) {
    stage();
    timeline_.close(next_++);
  }

 private:
  EventTimeline& timeline_;
  std::size_t next_ = 0;
};

// The stage table: each stage's name with its seconds so far from `timeline` (stages not yet run: 0).
inline std::vector<std::pair<std::string, double>> stage_table(const std::vector<std::string>& stages,
                                                               EventTimeline& timeline) {
  const std::vector<double>& seconds = timeline.seconds();
  std::vector<std::pair<std::string, double>> table;
  for (std::size_t i = 0; i < stages.size(); ++i) table.emplace_back(stages[i], i < seconds.size() ? seconds[i] : 0.0);
  return table;
}

}  // namespace romp::engine
