// Formats `romp info` from what the build recorded and what the runtime answers now.
#include "host/cli/info_report.h"

#include <fmt/format.h>
#include <omp.h>

#include "host/backend_selection.h"

namespace romp::cli {
namespace {

const char* yes_no(bool value) { return value ? "yes" : "no"; }

std::string cuda_version(int encoded) {
  if (encoded == 0) return "none";
  return fmt::format("{}.{}", encoded / 1000, encoded % 1000 / 10);
}

}  // namespace

std::string info_report(const BuildInfo& build, const CudaProbe& cuda, const nn::TorchInfo& torch) {
  std::string text;
  auto line = [&text](const std::string& key, const std::string& value) {
    text += fmt::format("{:<22}{}\n", key, value);
  };
  line("romp", build.version);
  line("commit", build.commit);
  line("build type", build.build_type);
  line("C++ compiler", build.cxx_compiler);
  line("CUDA backend", build.cuda ? fmt::format("compiled (nvcc {}, architectures {})", build.cuda_compiler_version,
                                                build.cuda_architectures)
                                  : "not compiled");
  line("CUDA runtime/driver",
       fmt::format("{} / {}", cuda_version(cuda.runtime_version), cuda_version(cuda.driver_version)));
  line("LibTorch", fmt::format("{} (CUDA kernels: {}, CUDA available now: {})", torch.version,
                               yes_no(torch.compiled_with_cuda), yes_no(torch.cuda_available)));
  line("HDF5", build.hdf5_version);
  line("OpenMP threads", std::to_string(omp_get_max_threads()));
  line("OpenMP waits", openmp_wait_policy());
  if (cuda.devices.empty()) {
    line("CUDA devices", "none (" + cuda.status + ")");
  }
  for (const CudaDevice& device : cuda.devices) {
    line(fmt::format("CUDA device {}", device.ordinal),
         fmt::format("{}, sm_{}{}, {} SMs, {:.1f} GiB", device.name, device.compute_major, device.compute_minor,
                     device.multiprocessors, double(device.global_memory_bytes) / double(1ull << 30)));
  }
  line("default backend", cuda.devices.empty() ? "cpu" : "cuda");
  return text;
}

}  // namespace romp::cli
