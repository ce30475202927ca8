// Chooses the backend a run uses: CUDA if a device answers, else the CPU, unless the user insists.
#pragma once

#include <string>

#include "kernels/core/device.h"
#include "kernels/core/exec.h"

namespace romp {

enum class DeviceChoice { Auto, Cpu, Cuda };

// Parses the --device value; throws romp::Error naming the allowed values.
DeviceChoice parse_device_choice(const std::string& text);

// The CPU threads to run on for a --threads request: the request, or the machine's processor count
// with a warning where it asks for more (0 = OpenMP's default). A negative request is an error.
int cap_cpu_threads(int requested, int processors);

// Resolves `choice` against what `probe` found, with cpu_threads capped at this machine's processors.
// Asking for CUDA where none answers is an error that says why (not compiled in, or the runtime's own
// reason).
Exec select_exec(DeviceChoice choice, const CudaProbe& probe, int cpu_threads = 0);

// One line saying which backend a run uses and why, e.g. "backend: cuda (device 0: NVIDIA H100, sm_90)".
std::string describe_selection(const Exec& exec, const CudaProbe& probe);

// select_exec on this machine, making the chosen device current and logging the choice once per process.
Exec select_backend(DeviceChoice choice, int cpu_threads = 0);

}  // namespace romp
