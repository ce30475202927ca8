// Allocation and copies: aligned host memory on the CPU, cudaMalloc/cudaMemcpy on CUDA.
#include "kernels/core/memory.h"

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <string>

#include "kernels/core/error.h"
#include "kernels/core/guarded_memory.h"

#if defined(ROMP_WITH_CUDA)
#include "kernels/core/cuda_check.h"
#endif

namespace romp::memory {
namespace {

[[noreturn]] void no_cuda_backend() {
  throw Error("the CUDA backend is not compiled into this build of romp (configure with ROMP_CUDA=ON and nvcc)");
}

#if defined(ROMP_WITH_CUDA)
cudaMemcpyKind copy_kind(Backend destination, Backend source) {
  if (source == Backend::Cpu) return destination == Backend::Cpu ? cudaMemcpyHostToHost : cudaMemcpyHostToDevice;
  return destination == Backend::Cpu ? cudaMemcpyDeviceToHost : cudaMemcpyDeviceToDevice;
}
#endif

std::atomic<std::int64_t> allocations{0}, uploads{0}, downloads{0}, launches{0};

thread_local Capture* t_capture = nullptr;
thread_local bool t_inside_cpu_launch = false;

}  // namespace

Capture* open_capture() { return t_capture; }

CaptureScope::CaptureScope(Capture& capture) {
  ROMP_CHECK(t_capture == nullptr, "graph captures do not nest");
  t_capture = &capture;
}

CaptureScope::~CaptureScope() { t_capture = nullptr; }

void refuse_in_capture(const char* what) {
  if (t_capture == nullptr) return;
  throw Error(std::string(what) +
              " while a graph is being captured: a graph holds launches on the device alone (no allocation, "
              "transfer or host read of device memory between them; the CPU backend records a launch made "
              "through memory::launch_on_cpu)");
}

void check_capture_stream(Stream stream) {
  if (t_capture == nullptr || stream == t_capture->stream) return;
  throw Error("a launch on another stream than the one a graph is being captured on: pass the captured Exec's stream");
}

namespace detail {
bool inside_cpu_launch() { return t_inside_cpu_launch; }
InsideCpuLaunch::InsideCpuLaunch() : outer_(t_inside_cpu_launch) { t_inside_cpu_launch = true; }
InsideCpuLaunch::~InsideCpuLaunch() { t_inside_cpu_launch = outer_; }
}  // namespace detail

void* allocate(Backend backend, std::size_t bytes) {
  if (bytes == 0) return nullptr;
  refuse_in_capture(("an allocation of " + std::to_string(bytes) + " bytes").c_str());
  allocations.fetch_add(1, std::memory_order_relaxed);
  if (backend == Backend::Cpu) {
    if (guard_enabled()) {
      void* pointer = guarded::allocate(bytes);
      ROMP_CHECK(pointer != nullptr, "out of guarded host memory allocating " + std::to_string(bytes) + " bytes");
      return pointer;
    }
    const std::size_t rounded = (bytes + kHostAlignment - 1) / kHostAlignment * kHostAlignment;
    void* pointer = std::aligned_alloc(kHostAlignment, rounded);
    ROMP_CHECK(pointer != nullptr, "out of host memory allocating " + std::to_string(bytes) + " bytes");
    return pointer;
  }
#if defined(ROMP_WITH_CUDA)
  void* pointer = nullptr;
  ROMP_CUDA_CHECK(cudaMalloc(&pointer, bytes));
  return pointer;
#else
  no_cuda_backend();
#endif
}

void release(Backend backend, void* pointer) noexcept {
  if (pointer == nullptr) return;
  if (backend == Backend::Cpu) {
    if (!guarded::release(pointer)) std::free(pointer);
    return;
  }
#if defined(ROMP_WITH_CUDA)
  ROMP_CUDA_CHECK_NOTHROW(cudaFree(pointer));
#endif
}

namespace {

// copy() without the launch count: uploads and downloads count as themselves.
void copy_bytes(void* destination, Backend destination_backend, const void* source, Backend source_backend,
                std::size_t bytes, Stream stream) {
  if (destination_backend == Backend::Cpu && source_backend == Backend::Cpu) {
    const DeviceAccess transfer;
    std::memcpy(destination, source, bytes);
    return;
  }
#if defined(ROMP_WITH_CUDA)
  ROMP_CUDA_CHECK(cudaMemcpyAsync(destination, source, bytes, copy_kind(destination_backend, source_backend), stream));
  // Between two device buffers the stream orders the copy for every later use: no wait (and none to break a
  // CUDA graph's capture).
  if (destination_backend == Backend::Cpu || source_backend == Backend::Cpu)
    ROMP_CUDA_CHECK(cudaStreamSynchronize(stream));
#else
  (void)stream;
  no_cuda_backend();
#endif
}

}  // namespace

void copy(void* destination, Backend destination_backend, const void* source, Backend source_backend, std::size_t bytes,
          Stream stream) {
  if (bytes == 0) return;
  if (destination_backend == Backend::Cpu && source_backend == Backend::Cpu) {
    // Between two buffers of the CPU backend: its device work, a launch.
    launch_on_cpu(stream, 1,
                  [=] { copy_bytes(destination, destination_backend, source, source_backend, bytes, stream); });
    return;
  }
  if (destination_backend == Backend::Cpu || source_backend == Backend::Cpu) refuse_in_capture("a host copy");
  check_capture_stream(stream);
  note_launch();
  copy_bytes(destination, destination_backend, source, source_backend, bytes, stream);
}

void note_launch(int count) {
  if (detail::inside_cpu_launch()) return;  // part of a launch counted already
  if (t_capture != nullptr) {
    t_capture->launches += count;
    return;
  }
  launches.fetch_add(count, std::memory_order_relaxed);
}

void upload(void* destination, Backend backend, const void* host, std::size_t bytes, Stream stream) {
  if (bytes == 0) return;
  refuse_in_capture(("an upload of " + std::to_string(bytes) + " bytes").c_str());
  uploads.fetch_add(1, std::memory_order_relaxed);
  copy_bytes(destination, backend, host, Backend::Cpu, bytes, stream);
}

void download(void* host, const void* source, Backend backend, std::size_t bytes, Stream stream) {
  if (bytes == 0) return;
  refuse_in_capture(("a download of " + std::to_string(bytes) + " bytes").c_str());
  downloads.fetch_add(1, std::memory_order_relaxed);
  copy_bytes(host, Backend::Cpu, source, backend, bytes, stream);
}

Traffic traffic() {
  Traffic counts;
  counts.allocations = allocations.load(std::memory_order_relaxed);
  counts.uploads = uploads.load(std::memory_order_relaxed);
  counts.downloads = downloads.load(std::memory_order_relaxed);
  counts.launches = launches.load(std::memory_order_relaxed);
  return counts;
}

void fill_zero(void* destination, Backend backend, std::size_t bytes, Stream stream) {
  if (bytes == 0) return;
  if (backend == Backend::Cpu) {
    launch_on_cpu(stream, 1, [=] {
      const DeviceAccess transfer;
      std::memset(destination, 0, bytes);
    });
    return;
  }
  check_capture_stream(stream);
  note_launch();
#if defined(ROMP_WITH_CUDA)
  ROMP_CUDA_CHECK(cudaMemsetAsync(destination, 0, bytes, stream));
#else
  (void)stream;
  no_cuda_backend();
#endif
}

}  // namespace romp::memory
