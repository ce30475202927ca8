// ROMP_CUDA_CHECK: every CUDA runtime call is checked and a failure throws romp::Error.
// Only for translation units that see the CUDA runtime (ROMP_WITH_CUDA builds).
#pragma once

#include <cuda_runtime_api.h>

#include "kernels/core/error.h"

namespace romp::detail {

[[noreturn]] void throw_cuda_error(cudaError_t status, const char* file, int line, const char* expression);
// For destructors, which must not throw: prints the same message to stderr.
void report_cuda_error(cudaError_t status, const char* file, int line, const char* expression) noexcept;

}  // namespace romp::detail

#define ROMP_CUDA_CHECK(expression)                                                         \
  do {                                                                                      \
    const cudaError_t romp_cuda_status_ = (expression);                                     \
    if (romp_cuda_status_ != cudaSuccess)                                                   \
      ::romp::detail::throw_cuda_error(romp_cuda_status_, __FILE__, __LINE__, #expression); \
  } while (false)

#define ROMP_CUDA_CHECK_NOTHROW(expression)                                                  \
  do {                                                                                       \
    const cudaError_t romp_cuda_status_ = (expression);                                      \
    if (romp_cuda_status_ != cudaSuccess)                                                    \
      ::romp::detail::report_cuda_error(romp_cuda_status_, __FILE__, __LINE__, #expression); \
  } while (false)
