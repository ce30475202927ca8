// Messages for failed CUDA runtime calls: the call, the error name and its description.
#include "kernels/core/cuda_check.h"

#include <cstdio>
#include <string>

namespace romp::detail {
namespace {

std::string cuda_message(cudaError_t status) {
  return std::string("CUDA call failed: ") + cudaGetErrorName(status) + " (" + cudaGetErrorString(status) + ")";
}

}  // namespace

void throw_cuda_error(cudaError_t status, const char* file, int line, const char* expression) {
  throw Error(cuda_message(status), file, line, expression);
}

void report_cuda_error(cudaError_t status, const char* file, int line, const char* expression) noexcept {
  std::fprintf(stderr, "%s:%d: %s [%s]\n", file, line, cuda_message(status).c_str(), expression);
}

}  // namespace romp::detail
