// StageClock: times the stages of one substep in pipeline order on the simulation's timeline (CUDA
// events on a GPU, a steady clock on the CPU; kernels/core/event_timeline.h), each stage's time going
// to its interval: the index of its entry in the simulation's stage table, and counts each stage's
// launches (memory::traffic) there too. Nothing waits for the device.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "kernels/core/event_timeline.h"
#include "kernels/core/exec.h"
#include "kernels/core/memory.h"
#include "kernels/core/stream_graph.h"

namespace romp::engine {

class StageClock {
 public:
  // `launches`: the launches of each stage so far, grown as stages run.
  StageClock(EventTimeline& timeline, std::vector<std::int64_t>& launches)
      : timeline_(&timeline), launches_(&launches) {
    timeline_->open();
  }
  // Runs the stages untimed: while a CUDA graph is captured, when they run later as one launch.
  static StageClock untimed() { return StageClock(); }

  // Runs the next stage and marks its end.
  template <class Stage>
  void operator()(Stage&& stage) {
    if (timeline_ == nullptr) {
      stage();
      return;
    }
    const std::int64_t before = memory::traffic().launches;
    stage();
    timeline_->close(next_);
    if (launches_->size() <= next_) launches_->resize(next_ + 1, 0);
    (*launches_)[next_++] += memory::traffic().launches - before;
  }

 private:
  StageClock() = default;

  EventTimeline* timeline_ = nullptr;
  std::vector<std::int64_t>* launches_ = nullptr;
  std::size_t next_ = 0;
};

// Replays `graph` (substeps captured as one CUDA graph) as stage `stage` of the table: its time on `timeline`,
// one launch in `launches`. A replay's stages are not told apart.
inline void replay_as_stage(const StreamGraph& graph, const Exec& exec, std::size_t stage, EventTimeline& timeline,
                            std::vector<std::int64_t>& launches) {
  timeline.open();
  graph.replay(exec);
  timeline.close(stage);
  if (launches.size() <= stage) launches.resize(stage + 1, 0);
  ++launches[stage];
}

// The stage table: each stage's name with its seconds so far from `timeline` (stages not yet run: 0).
inline std::vector<std::pair<std::string, double>> stage_table(const std::vector<std::string>& stages,
                                                               EventTimeline& timeline) {
  const std::vector<double>& seconds = timeline.seconds();
  std::vector<std::pair<std::string, double>> table;
  for (std::size_t i = 0; i < stages.size(); ++i) table.emplace_back(stages[i], i < seconds.size() ? seconds[i] : 0.0);
  return table;
}

// Each stage's name with its launches so far.
inline std::vector<std::pair<std::string, std::int64_t>> stage_launch_table(const std::vector<std::string>& stages,
                                                                            const std::vector<std::int64_t>& launches) {
  std::vector<std::pair<std::string, std::int64_t>> table;
  for (std::size_t i = 0; i < stages.size(); ++i) table.emplace_back(stages[i], i < launches.size() ? launches[i] : 0);
  return table;
}

}  // namespace romp::engine
