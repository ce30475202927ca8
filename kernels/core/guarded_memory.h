// Guarded CPU memory: the CPU backend made to fault where the CUDA backend would.
//
// On a GPU, host code that dereferences a DeviceBuffer's memory crashes (or reads garbage); on the
// CPU backend the same code works, so CI without a GPU cannot see it. In guarded mode every CPU
// allocation of memory::allocate lives in pages that host code cannot touch: they open only while
// the CPU does what the device would do — a for_each loop, another kernel's CPU path, an explicit
// transfer (memory::copy, upload, download, fill_zero), LibTorch ops on engine buffers inside a
// TorchStreamScope — each of which holds a DeviceAccess. Any other touch of that memory is a
// SIGSEGV, reported with the faulting address and a backtrace, exactly where a GPU run would break.
//
// Guarded mode is for tests (the test binaries' --backend=guarded): it costs two mprotect calls per
// launch, and a thread that holds DeviceAccess opens the pages to every thread meanwhile.
#pragma once

#include <cstddef>

namespace romp::memory {

// Turns guarded mode on for the rest of the process; call before the first allocation. Idempotent.
void enable_guard();
bool guard_enabled();

// While any DeviceAccess is alive, guarded memory is readable and writable (from every thread). Free
// outside guarded mode (one relaxed atomic load).
class DeviceAccess {
 public:
  DeviceAccess();
  ~DeviceAccess();
  DeviceAccess(const DeviceAccess&) = delete;
  DeviceAccess& operator=(const DeviceAccess&) = delete;

 private:
  bool counted_;
};

namespace guarded {
// memory::allocate and release on the CPU backend in guarded mode: page-aligned blocks of one arena.
void* allocate(std::size_t bytes);
// True (and the block released) when `pointer` came from allocate().
bool release(void* pointer) noexcept;
}  // namespace guarded

}  // namespace romp::memory
