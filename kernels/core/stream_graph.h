// StreamGraph: the launches a piece of host code enqueues on one stream, captured once and replayed as
// one launch as often as wanted (a CUDA graph; on the CPU backend, the recorded launches run in order).
//
// A replay runs the launches with the arguments they had at capture (pointers, sizes, scalars): what must
// change from replay to replay has to be read from device memory the launches share with the host's
// other work. The CPU backend records each launch's functor as CUDA records its parameters, so a test on
// the CPU catches a value baked in at capture that the eager path would have updated, and a capture that
// needs the host between launches (an allocation, a transfer, a host read of a device value) is refused on
// either backend (memory::Capture).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "kernels/core/exec.h"

// Same type as cudaGraphExec_t, declared here so CPU-only code need not include the CUDA headers.
struct CUgraphExec_st;

namespace romp {

// A stream of its own for work that is captured (CUDA cannot capture the legacy default stream). Created
// blocking, so it stays ordered with work on the legacy default stream as before. On the CPU a token that
// no call dereferences, so that a launch on another stream inside a capture is refused there as on CUDA.
class OwnedStream {
 public:
  explicit OwnedStream(Backend backend);
  ~OwnedStream();
  OwnedStream(const OwnedStream&) = delete;
  OwnedStream& operator=(const OwnedStream&) = delete;

  Stream get() const { return stream_; }

 private:
  Stream stream_ = nullptr;
};

// `exec`, on `owned` where it runs on the default stream (the legacy one on CUDA).
Exec with_capturable_stream(const Exec& exec, const OwnedStream& owned);

class StreamGraph {
 public:
  StreamGraph() = default;
  ~StreamGraph();
  StreamGraph(const StreamGraph&) = delete;
  StreamGraph& operator=(const StreamGraph&) = delete;

  // Records what `enqueue` launches on exec.stream, running none of it (CUDA: a stream other than the legacy
  // default one). Replaces an earlier capture. A throw from `enqueue` (a refusal included) ends the capture,
  // leaves the graph empty and propagates.
  void capture(const Exec& exec, const std::function<void()>& enqueue);
  // The captured launches, in order, on exec.stream: one launch (memory::traffic counts it).
  void replay(const Exec& exec) const;
  bool empty() const { return !captured_; }
  // The launches `enqueue` made (each a node of the CUDA graph).
  std::int64_t launches() const { return launches_; }

 private:
  void clear();

  bool captured_ = false;
  std::int64_t launches_ = 0;
  std::vector<std::function<void()>> cpu_work_;
  CUgraphExec_st* graph_ = nullptr;
};

}  // namespace romp
