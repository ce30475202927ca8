// DeviceTimer: cudaEventElapsedTime on CUDA streams, std::chrono::steady_clock on the CPU.
#include "kernels/core/device_timer.h"

#include "kernels/core/error.h"

#if defined(ROMP_WITH_CUDA)
#include "kernels/core/cuda_check.h"
#endif

namespace romp {

DeviceTimer::DeviceTimer(const Exec& exec) : exec_(exec) {
  if (!exec_.is_cuda()) return;
#if defined(ROMP_WITH_CUDA)
  ROMP_CUDA_CHECK(cudaEventCreate(&begin_));
  ROMP_CUDA_CHECK(cudaEventCreate(&end_));
#else
  throw Error("DeviceTimer: the CUDA backend is not compiled into this build");
#endif
}

DeviceTimer::~DeviceTimer() {
#if defined(ROMP_WITH_CUDA)
  if (begin_ != nullptr) ROMP_CUDA_CHECK_NOTHROW(cudaEventDestroy(begin_));
  if (end_ != nullptr) ROMP_CUDA_CHECK_NOTHROW(cudaEventDestroy(end_));
#endif
}

void DeviceTimer::start() {
#if defined(ROMP_WITH_CUDA)
  if (exec_.is_cuda()) {
    ROMP_CUDA_CHECK(cudaEventRecord(begin_, exec_.stream));
    return;
  }
#endif
  host_start_ = std::chrono::steady_clock::now();
}

double DeviceTimer::stop() {
#if defined(ROMP_WITH_CUDA)
  if (exec_.is_cuda()) {
    ROMP_CUDA_CHECK(cudaEventRecord(end_, exec_.stream));
    ROMP_CUDA_CHECK(cudaEventSynchronize(end_));
    float milliseconds = 0.0f;
    ROMP_CUDA_CHECK(cudaEventElapsedTime(&milliseconds, begin_, end_));
    return double(milliseconds) * 1e-3;
  }
#endif
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - host_start_).count();
}

}  // namespace romp
