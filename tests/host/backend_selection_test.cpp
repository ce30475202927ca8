// Backend selection: CUDA when a device answers, the CPU otherwise, and a clear error when the
// user insists on a device that is not there.
#include <gtest/gtest.h>
#include <omp.h>

#include <string>

#include "host/backend_selection.h"
#include "kernels/core/error.h"

namespace romp {
namespace {

CudaProbe probe_without_devices(bool compiled) {
  CudaProbe probe;
  probe.compiled = compiled;
  probe.status = compiled ? "cudaErrorNoDevice: no CUDA-capable device is detected"
                          : "the CUDA backend is not compiled into this build";
  return probe;
}

CudaProbe probe_with_one_device() {
  CudaProbe probe;
  probe.compiled = true;
  probe.devices.push_back(CudaDevice{0, "Test GPU", 9, 0, 132, std::size_t(80) << 30});
  probe.status = "ok";
  return probe;
}

TEST(BackendSelection, AutoPrefersCudaWhenADeviceAnswers) {
  EXPECT_EQ(select_exec(DeviceChoice::Auto, probe_with_one_device()).backend, Backend::Cuda);
  EXPECT_EQ(select_exec(DeviceChoice::Auto, probe_without_devices(true)).backend, Backend::Cpu);
  EXPECT_EQ(select_exec(DeviceChoice::Auto, probe_without_devices(false)).backend, Backend::Cpu);
}

TEST(BackendSelection, CpuChoiceOverridesAnAvailableDevice) {
  const Exec exec = select_exec(DeviceChoice::Cpu, probe_with_one_device(), 1);
  EXPECT_EQ(exec.backend, Backend::Cpu);
  EXPECT_EQ(exec.threads, 1);
}

// `--threads 100000` once crashed inside the OpenMP runtime: a request beyond the machine's processors
// runs on as many as it has.
TEST(BackendSelection, ThreadsBeyondTheMachinesProcessorsAreCapped) {
  EXPECT_EQ(cap_cpu_threads(100000, 16), 16);
  EXPECT_EQ(cap_cpu_threads(17, 16), 16);
  EXPECT_EQ(cap_cpu_threads(16, 16), 16);
  EXPECT_EQ(cap_cpu_threads(3, 16), 3);
  EXPECT_EQ(cap_cpu_threads(0, 16), 0);
  EXPECT_THROW(cap_cpu_threads(-1, 16), Error);
  EXPECT_EQ(select_exec(DeviceChoice::Cpu, probe_without_devices(true), 100000).threads, omp_get_num_procs());
}

// The default thread count is fixed when the backend is chosen: LibTorch sets OpenMP's count to its own
// default at its first parallel operation (1 on some machines), which once dropped learned-law runs to one
// thread.
TEST(BackendSelection, DefaultThreadCountIsFixedAtSelection) {
  const Exec exec = select_exec(DeviceChoice::Cpu, probe_without_devices(true));
  EXPECT_EQ(exec.threads, omp_get_max_threads());  // not 0, which would ask OpenMP again at every loop
  EXPECT_GT(exec.threads, 0);
}

TEST(BackendSelection, CudaWithoutADeviceSaysWhy) {
  try {
    select_exec(DeviceChoice::Cuda, probe_without_devices(true));
    FAIL() << "selected CUDA with no device";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("no CUDA-capable device"), std::string::npos);
  }
  try {
    select_exec(DeviceChoice::Cuda, probe_without_devices(false));
    FAIL() << "selected CUDA in a build without it";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("no CUDA backend"), std::string::npos);
  }
}

TEST(BackendSelection, ParsesOnlyTheDocumentedChoices) {
  EXPECT_EQ(parse_device_choice("auto"), DeviceChoice::Auto);
  EXPECT_EQ(parse_device_choice("cpu"), DeviceChoice::Cpu);
  EXPECT_EQ(parse_device_choice("cuda"), DeviceChoice::Cuda);
  EXPECT_THROW(parse_device_choice("gpu"), Error);
}

TEST(BackendSelection, DescriptionNamesTheDeviceOrTheReason) {
  const CudaProbe with = probe_with_one_device();
  EXPECT_EQ(describe_selection(Exec::cuda(0), with), "backend: cuda (device 0: Test GPU, sm_90)");
  const CudaProbe without = probe_without_devices(true);
  const std::string cpu = describe_selection(Exec::cpu(2), without);
  EXPECT_NE(cpu.find("backend: cpu (2 OpenMP threads; waits: "), std::string::npos);
  EXPECT_NE(cpu.find("no CUDA-capable device"), std::string::npos);
}

TEST(BackendSelection, ThisMachineAnswersConsistently) {
  // What the real probe finds decides the automatic choice; the test holds on any machine.
  const CudaProbe probe = probe_cuda();
  const Exec exec = select_exec(DeviceChoice::Auto, probe);
  EXPECT_EQ(exec.is_cuda(), !probe.devices.empty());
#if !defined(ROMP_WITH_CUDA)
  EXPECT_FALSE(probe.compiled);
#endif
}

}  // namespace
}  // namespace romp
