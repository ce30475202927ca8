// Exec: where a kernel runs (CPU threads or a CUDA device and stream).
#pragma once

#include <string>

// Same type as cudaStream_t, declared here so CPU-only code need not include the CUDA headers.
struct CUstream_st;

namespace romp {

using Stream = CUstream_st*;

enum class Backend { Cpu, Cuda };

inline const char* to_string(Backend backend) { return backend == Backend::Cpu ? "cpu" : "cuda"; }

struct Exec {
  Backend backend = Backend::Cpu;
  // CPU: OpenMP threads for each parallel loop; 0 leaves OpenMP's default (OMP_NUM_THREADS).
  int threads = 0;
  // CUDA: the device ordinal and the stream kernels are queued on (nullptr = default stream).
  int device = 0;
  Stream stream = nullptr;

  static Exec cpu(int threads = 0) { return Exec{Backend::Cpu, threads, 0, nullptr}; }
  static Exec cuda(int device = 0, Stream stream = nullptr) { return Exec{Backend::Cuda, 0, device, stream}; }

  bool is_cuda() const { return backend == Backend::Cuda; }
};

// Blocks until all work queued on `exec` has finished (a no-op on the CPU, whose loops are synchronous).
void synchronize(const Exec& exec);

}  // namespace romp
