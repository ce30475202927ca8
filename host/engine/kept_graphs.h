// KeptGraphs: the CUDA graphs (kernels/core/stream_graph.h) of a simulation's runs of substeps, each captured
// for a key (what the graph bakes in: Δt, the substep count, the inputs, the buffers it starts from) and kept
// for replay. When a new key comes and all are taken, the graph used longest ago is captured over: a frame's
// substep count may alternate between a few values from frame to frame.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "kernels/core/exec.h"
#include "kernels/core/stream_graph.h"

namespace romp::engine {

template <class Key>
class KeptGraphs {
 public:
  explicit KeptGraphs(std::size_t kept) : kept_(kept) {}

  // The graph for `key`, captured from what `enqueue` launches on exec.stream when none is kept for it. A throw
  // from the capture (a refusal included) leaves no graph for the key and propagates.
  const StreamGraph& get(const Exec& exec, const Key& key, const std::function<void()>& enqueue) {
    ++uses_;
    for (Kept& kept : graphs_)
      if (kept.key == key) {
        kept.last_use = uses_;
        return *kept.graph;
      }
    typename std::vector<Kept>::iterator slot;
    if (graphs_.size() < kept_) {
      graphs_.push_back({key, std::make_unique<StreamGraph>(), uses_});
      slot = graphs_.end() - 1;
    } else {
      slot = std::min_element(graphs_.begin(), graphs_.end(),
                              [](const Kept& a, const Kept& b) { return a.last_use < b.last_use; });
      *slot = {key, std::make_unique<StreamGraph>(), uses_};
    }
    try {
      slot->graph->capture(exec, enqueue);
    } catch (...) {
      graphs_.erase(slot);
      throw;
    }
    ++captures_;
    return *slot->graph;
  }

  std::int64_t captures() const { return captures_; }

 private:
  struct Kept {
    Key key;
    std::unique_ptr<StreamGraph> graph;
    std::int64_t last_use = 0;
  };
  std::size_t kept_;
  std::vector<Kept> graphs_;
  std::int64_t uses_ = 0, captures_ = 0;
};

}  // namespace romp::engine
