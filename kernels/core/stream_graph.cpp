// StreamGraph: cudaStreamBeginCapture / cudaGraphLaunch on CUDA, the recorded launches on the CPU.
#include "kernels/core/stream_graph.h"

#include "kernels/core/error.h"
#include "kernels/core/memory.h"

#if defined(ROMP_WITH_CUDA)
#include "kernels/core/cuda_check.h"
#endif

namespace romp {

OwnedStream::OwnedStream(Backend backend) {
  if (backend != Backend::Cuda) {
    stream_ = reinterpret_cast<Stream>(this);  // a token, unique while this object lives
    return;
  }
#if defined(ROMP_WITH_CUDA)
  ROMP_CUDA_CHECK(cudaStreamCreate(&stream_));
#else
  throw Error("OwnedStream: the CUDA backend is not compiled into this build");
#endif
}

OwnedStream::~OwnedStream() {
#if defined(ROMP_WITH_CUDA)
  if (stream_ != nullptr && stream_ != reinterpret_cast<Stream>(this))
    ROMP_CUDA_CHECK_NOTHROW(cudaStreamDestroy(stream_));
#endif
}

Exec with_capturable_stream(const Exec& exec, const OwnedStream& owned) {
  if (exec.stream != nullptr) return exec;
  Exec own = exec;
  own.stream = owned.get();
  return own;
}

StreamGraph::~StreamGraph() { clear(); }

void StreamGraph::clear() {
#if defined(ROMP_WITH_CUDA)
  if (graph_ != nullptr) ROMP_CUDA_CHECK_NOTHROW(cudaGraphExecDestroy(graph_));
#endif
  graph_ = nullptr;
  cpu_work_.clear();
  launches_ = 0;
  captured_ = false;
}

void StreamGraph::capture(const Exec& exec, const std::function<void()>& enqueue) {
  clear();
  memory::Capture record;
  record.stream = exec.stream;
  if (!exec.is_cuda()) {
    {
      const memory::CaptureScope scope(record);
      enqueue();
    }
    cpu_work_ = std::move(record.cpu_work);
    launches_ = record.launches;
    captured_ = true;
    return;
  }
#if defined(ROMP_WITH_CUDA)
  ROMP_CHECK(exec.stream != nullptr,
             "a CUDA graph is captured on a stream of its own, not the legacy default stream (see OwnedStream)");
  // Thread-local: another thread's CUDA calls meanwhile are no part of this capture, and are not refused.
  ROMP_CUDA_CHECK(cudaStreamBeginCapture(exec.stream, cudaStreamCaptureModeThreadLocal));
  cudaGraph_t graph = nullptr;
  try {
    const memory::CaptureScope scope(record);
    enqueue();
  } catch (...) {
    if (cudaStreamEndCapture(exec.stream, &graph) == cudaSuccess && graph != nullptr) cudaGraphDestroy(graph);
    cudaGetLastError();  // the failed capture's error is the exception's, not the next call's
    throw;
  }
  ROMP_CUDA_CHECK(cudaStreamEndCapture(exec.stream, &graph));
  const cudaError_t instantiated = cudaGraphInstantiate(&graph_, graph, 0);
  ROMP_CUDA_CHECK_NOTHROW(cudaGraphDestroy(graph));
  ROMP_CUDA_CHECK(instantiated);
  launches_ = record.launches;
  captured_ = true;
#else
  throw Error("StreamGraph: the CUDA backend is not compiled into this build");
#endif
}

void StreamGraph::replay(const Exec& exec) const {
  ROMP_CHECK(captured_, "StreamGraph::replay before a capture");
  memory::refuse_in_capture("a graph's replay");
  memory::note_launch();
  if (!exec.is_cuda()) {
    // Launches made by the recorded work are part of this one.
    const memory::detail::InsideCpuLaunch inside;
    for (const std::function<void()>& work : cpu_work_) work();
    return;
  }
#if defined(ROMP_WITH_CUDA)
  ROMP_CUDA_CHECK(cudaGraphLaunch(graph_, exec.stream));
#if !defined(NDEBUG) || defined(ROMP_SYNC_LAUNCHES)
  ROMP_CUDA_CHECK(cudaStreamSynchronize(exec.stream));  // a fault of the graph's kernels, surfaced here
#endif
#endif
}

}  // namespace romp
