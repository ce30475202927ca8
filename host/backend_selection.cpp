// Runtime backend selection and its one-time report.
#include "host/backend_selection.h"

#include <omp.h>
#include <spdlog/spdlog.h>

#include <cstdlib>
#include <mutex>

#include "kernels/core/error.h"

namespace romp {

DeviceChoice parse_device_choice(const std::string& text) {
  if (text == "auto") return DeviceChoice::Auto;
  if (text == "cpu") return DeviceChoice::Cpu;
  if (text == "cuda") return DeviceChoice::Cuda;
  throw Error("--device '" + text + "': allowed values are auto, cpu, cuda");
}

int cap_cpu_threads(int requested, int processors) {
  ROMP_CHECK(requested >= 0, "--threads must be >= 0 (0 = OpenMP default), got " + std::to_string(requested));
  if (requested <= processors) return requested;
  // More threads than processors only wait on each other (and thousands exhaust the OpenMP runtime).
  spdlog::warn("--threads {}: this machine has {} processors; using {}", requested, processors, processors);
  return processors;
}

Exec select_exec(DeviceChoice choice, const CudaProbe& probe, int cpu_threads) {
  cpu_threads = cap_cpu_threads(cpu_threads, omp_get_num_procs());
  const bool cuda_ready = !probe.devices.empty();
  if (choice == DeviceChoice::Cuda && !cuda_ready) {
    if (!probe.compiled)
      throw Error("--device cuda: this build of romp has no CUDA backend (rebuild with nvcc and ROMP_CUDA=AUTO or ON)");
    throw Error("--device cuda: no CUDA device answered (" + probe.status + ")");
  }
  if (choice != DeviceChoice::Cpu && cuda_ready) return Exec::cuda(probe.devices.front().ordinal);
  // OpenMP's default, read now and kept: a CPU loop with threads = 0 asks OpenMP each time, and LibTorch
  // changes OpenMP's count at its first parallel operation to its own default (Debian's LibTorch 1.13 on a
  // 2-core machine: 1), so a run that loaded a learned law fell to one thread.
  return Exec::cpu(cpu_threads > 0 ? cpu_threads : omp_get_max_threads());
}

std::string describe_selection(const Exec& exec, const CudaProbe& probe) {
  if (exec.is_cuda()) {
    for (const CudaDevice& device : probe.devices) {
      if (device.ordinal != exec.device) continue;
      return "backend: cuda (device " + std::to_string(device.ordinal) + ": " + device.name + ", sm_" +
             std::to_string(device.compute_major) + std::to_string(device.compute_minor) + ")";
    }
  }
  const int threads = exec.threads > 0 ? exec.threads : omp_get_max_threads();
  std::string line =
      "backend: cpu (" + std::to_string(threads) + " OpenMP threads; waits: " + openmp_wait_policy() + ")";
  if (probe.devices.empty()) line += "; CUDA: " + probe.status;
  return line;
}

Exec select_backend(DeviceChoice choice, int cpu_threads) {
  const CudaProbe probe = probe_cuda();
  const Exec exec = select_exec(choice, probe, cpu_threads);
  if (exec.is_cuda()) set_cuda_device(exec.device);
  static std::once_flag reported;
  std::call_once(reported, [&] { spdlog::info("{}", describe_selection(exec, probe)); });
  return exec;
}

std::string openmp_wait_policy() {
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  if (policy == nullptr) return "the OpenMP runtime's default";
  // The launcher marks the policy it chose, so a report can tell it from the user's.
  const char* chosen = std::getenv("ROMP_OPENMP_WAITS");
  return std::string(policy) + (chosen != nullptr ? " (romp's default)" : " (OMP_WAIT_POLICY)");
}

}  // namespace romp
