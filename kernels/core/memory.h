// Raw allocation, copies and fills on either backend; DeviceBuffer<T> is built on these.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "kernels/core/exec.h"

namespace romp::memory {

// CPU memory is aligned to a cache line so SoA planes start on a line boundary, as on the GPU.
inline constexpr std::size_t kHostAlignment = 64;

// Returns nullptr for zero bytes. Throws romp::Error when the backend is unavailable or memory runs out.
void* allocate(Backend backend, std::size_t bytes);
void release(Backend backend, void* pointer) noexcept;

// Copies `bytes` between any two backends. The copy is ordered after earlier work on `stream`; one
// that reads or writes host memory is complete when the call returns, so that memory may be reused at
// once, and one between two device buffers returns at once (later work on `stream` sees it done).
void copy(void* destination, Backend destination_backend, const void* source, Backend source_backend, std::size_t bytes,
          Stream stream = nullptr);

// copy() from host memory to `backend` memory (upload) or back (download), counted in traffic().
void upload(void* destination, Backend backend, const void* host, std::size_t bytes, Stream stream = nullptr);
void download(void* host, const void* source, Backend backend, std::size_t bytes, Stream stream = nullptr);

// What the host has spent since the process started, on either backend: allocations of a byte or more
// (cudaMalloc on CUDA, whose matching cudaFree synchronises the device) and non-empty uploads and
// downloads (blocking round trips on CUDA, memcpy on the CPU). A loop's budget of both can so be
// tested on a machine without a GPU.
// Launches: the device work the host enqueues, each a few microseconds of its time on CUDA outside a CUDA
// graph: for_each's kernels, romp's own, a CUB primitive (one, whatever kernels it runs inside), a memset, a
// copy between device buffers. Counted the same on either backend where both run the same calls (a
// for_each_bounded launch counts even where the CPU finds nothing to run, as CUDA launches the bound).
struct Traffic {
  std::int64_t allocations = 0, uploads = 0, downloads = 0, launches = 0;
};
Traffic traffic();
// Counts `count` launches (for_each and the other launchers call it).
void note_launch(int count = 1);

// Sets `bytes` to zero, ordered on `stream` (asynchronous on CUDA).
void fill_zero(void* destination, Backend backend, std::size_t bytes, Stream stream = nullptr);

// A graph capture open on this thread (kernels/core/stream_graph.h). While one is open, launches are
// recorded instead of run (CUDA's stream capture records its own; the CPU backend's are kept here, each
// with its arguments as they were at capture, as a CUDA graph keeps them) and counted toward the graph, and
// what a graph cannot hold is refused with romp::Error naming it: an allocation, an upload or a download,
// and on the CPU a host touch of device memory (memory::DeviceAccess) outside a recorded launch, which on
// CUDA would read a value before the graph has computed it.
struct Capture {
  Stream stream = nullptr;  // the stream captured: a launch on another is refused
  std::vector<std::function<void()>> cpu_work;
  std::int64_t launches = 0;
};
// This thread's open capture, or nullptr.
Capture* open_capture();
// Opens `capture` on this thread for its lifetime (captures do not nest).
class CaptureScope {
 public:
  explicit CaptureScope(Capture& capture);
  ~CaptureScope();
  CaptureScope(const CaptureScope&) = delete;
  CaptureScope& operator=(const CaptureScope&) = delete;
};
// Throws romp::Error when a capture is open on this thread: `what` (e.g. "a download of 8 bytes") cannot be
// part of a graph.
void refuse_in_capture(const char* what);

namespace detail {
// Whether this thread runs inside one counted CPU launch (launch_on_cpu's work, or a replayed graph):
// launches made from there are part of it, neither counted nor recorded again.
bool inside_cpu_launch();
class InsideCpuLaunch {
 public:
  InsideCpuLaunch();
  ~InsideCpuLaunch();
  InsideCpuLaunch(const InsideCpuLaunch&) = delete;
  InsideCpuLaunch& operator=(const InsideCpuLaunch&) = delete;

 private:
  bool outer_;
};
}  // namespace detail

// Throws romp::Error when a capture is open on this thread and `stream` is not the one it captures (CUDA
// would refuse the launch, or order it outside the graph; the CPU backend's streams are tokens, so a test on
// the CPU sees the same mistake).
void check_capture_stream(Stream stream);

// `count` launches' worth of device work on the CPU backend, ordered on `stream` (a for_each loop, a CUB
// primitive's stand-in): run now and counted, or, while a capture is open on this thread, recorded (with a
// copy of `work`) to run when the graph is replayed. Launches that `work` itself makes are part of it.
template <class Work>
void launch_on_cpu(Stream stream, int count, const Work& work) {
  if (detail::inside_cpu_launch()) {
    work();
    return;
  }
  if (Capture* capture = open_capture()) {
    check_capture_stream(stream);
    capture->cpu_work.emplace_back(work);
    capture->launches += count;
    return;
  }
  note_launch(count);
  const detail::InsideCpuLaunch inside;
  work();
}

}  // namespace romp::memory
