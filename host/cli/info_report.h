// The text of `romp info`: version, commit, build configuration and the devices found.
#pragma once

#include <string>

#include "host/build_info.h"
#include "kernels/core/device.h"
#include "nn/torch_info.h"

namespace romp::cli {

std::string info_report(const BuildInfo& build, const CudaProbe& cuda, const nn::TorchInfo& torch);

}  // namespace romp::cli
