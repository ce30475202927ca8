// Reads LibTorch's version and CUDA support from the library itself.
#include "nn/torch_info.h"

#include <torch/cuda.h>
#include <torch/version.h>

namespace romp::nn {

TorchInfo torch_info() {
  TorchInfo info;
  info.version = TORCH_VERSION;
  info.compiled_with_cuda = ROMP_TORCH_CUDA != 0;
  info.cuda_available = torch::cuda::is_available();
  info.cuda_device_count = static_cast<int>(torch::cuda::device_count());
  return info;
}

}  // namespace romp::nn
