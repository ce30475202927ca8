// Raw allocation, copies and fills on either backend; DeviceBuffer<T> is built on these.
#pragma once

#include <cstddef>
#include <cstdint>

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

}  // namespace romp::memory
