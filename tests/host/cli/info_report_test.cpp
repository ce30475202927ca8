// `romp info` tells the truth about the build and the devices.
#include <gtest/gtest.h>

#include <string>

#include "host/cli/info_report.h"

namespace romp::cli {
namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(InfoReport, StatesWhetherCudaIsCompiledAsTheBuildDid) {
  const std::string report = info_report(build_info(), probe_cuda(), nn::torch_info());
#if defined(ROMP_WITH_CUDA)
  EXPECT_TRUE(build_info().cuda);
  EXPECT_TRUE(contains(report, "compiled (nvcc"));
#else
  EXPECT_FALSE(build_info().cuda);
  EXPECT_TRUE(contains(report, "not compiled"));
#endif
  EXPECT_TRUE(contains(report, build_info().version));
  EXPECT_TRUE(contains(report, build_info().commit));
  EXPECT_TRUE(contains(report, nn::torch_info().version));
}

TEST(InfoReport, ListsEachDeviceOrWhyThereIsNone) {
  CudaProbe probe;
  probe.compiled = true;
  probe.status = "cudaErrorNoDevice: no CUDA-capable device is detected";
  const nn::TorchInfo torch{"1.13.0", false, false, 0};
  EXPECT_TRUE(contains(info_report(build_info(), probe, torch), "none (cudaErrorNoDevice"));
  EXPECT_TRUE(contains(info_report(build_info(), probe, torch), "default backend       cpu"));

  probe.devices.push_back(CudaDevice{0, "NVIDIA H100 80GB HBM3", 9, 0, 132, std::size_t(80) << 30});
  const std::string report = info_report(build_info(), probe, torch);
  EXPECT_TRUE(contains(report, "NVIDIA H100 80GB HBM3, sm_90, 132 SMs, 80.0 GiB"));
  EXPECT_TRUE(contains(report, "default backend       cuda"));
}

}  // namespace
}  // namespace romp::cli
