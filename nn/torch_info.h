// What the linked LibTorch is and can do, for `romp info` and benchmark records.
#pragma once

#include <string>

namespace romp::nn {

struct TorchInfo {
  std::string version;      // e.g. "1.13.1"
  bool compiled_with_cuda;  // this LibTorch has CUDA kernels
  bool cuda_available;      // ... and a device answers now
  int cuda_device_count;
};

TorchInfo torch_info();

}  // namespace romp::nn
