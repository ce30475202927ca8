// What CUDA devices this process can use, asked of the runtime without failing when there is none.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace romp {

struct CudaDevice {
  int ordinal = 0;
  std::string name;
  int compute_major = 0;
  int compute_minor = 0;
  int multiprocessors = 0;
  std::size_t global_memory_bytes = 0;
};

struct CudaProbe {
  bool compiled = false;    // the CUDA backend is part of this build
  int driver_version = 0;   // e.g. 13000 for 13.0; 0 when no driver answers
  int runtime_version = 0;  // the CUDA runtime romp was linked against
  std::vector<CudaDevice> devices;
  std::string status;  // why there are no devices, in the runtime's words, or "ok"
};

// Asks the CUDA runtime once per call; never throws (a machine without a driver is a normal answer).
CudaProbe probe_cuda() noexcept;

// Makes `ordinal` the current device of the calling host thread; throws romp::Error if it fails.
void set_cuda_device(int ordinal);

}  // namespace romp
