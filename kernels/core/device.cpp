// CUDA device discovery and Exec synchronisation; without CUDA compiled in, an honest "none".
#include "kernels/core/device.h"

#include "kernels/core/error.h"
#include "kernels/core/exec.h"
#include "kernels/core/memory.h"

#if defined(ROMP_WITH_CUDA)
#include "kernels/core/cuda_check.h"
#endif

namespace romp {

CudaProbe probe_cuda() noexcept {
  CudaProbe probe;
#if defined(ROMP_WITH_CUDA)
  probe.compiled = true;
  cudaDriverGetVersion(&probe.driver_version);
  cudaRuntimeGetVersion(&probe.runtime_version);
  int count = 0;
  const cudaError_t status = cudaGetDeviceCount(&count);
  if (status != cudaSuccess) {
    probe.status = std::string(cudaGetErrorName(status)) + ": " + cudaGetErrorString(status);
    cudaGetLastError();  // clear it so a later, unrelated check does not report it again
    return probe;
  }
  for (int ordinal = 0; ordinal < count; ++ordinal) {
    cudaDeviceProp properties{};
    if (cudaGetDeviceProperties(&properties, ordinal) != cudaSuccess) continue;
    probe.devices.push_back(CudaDevice{ordinal, properties.name, properties.major, properties.minor,
                                       properties.multiProcessorCount, properties.totalGlobalMem});
  }
  probe.status = probe.devices.empty() ? "no CUDA device answered" : "ok";
#else
  probe.status = "the CUDA backend is not compiled into this build";
#endif
  return probe;
}

void set_cuda_device(int ordinal) {
#if defined(ROMP_WITH_CUDA)
  ROMP_CUDA_CHECK(cudaSetDevice(ordinal));
#else
  throw Error("cannot select CUDA device " + std::to_string(ordinal) +
              ": the CUDA backend is not compiled into this build");
#endif
}

void synchronize(const Exec& exec) {
  memory::refuse_in_capture("a wait for the device");
  if (!exec.is_cuda()) return;
#if defined(ROMP_WITH_CUDA)
  ROMP_CUDA_CHECK(cudaStreamSynchronize(exec.stream));
#else
  throw Error("synchronize: the CUDA backend is not compiled into this build");
#endif
}

}  // namespace romp
