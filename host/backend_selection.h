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

// Resolves `choice` against what `probe` found, with cpu_threads capped at this machine's processors
// (0: OpenMP's default now, kept in the Exec whatever later changes OpenMP's count).
// Asking for CUDA where none answers is an error that says why (not compiled in, or the runtime's own
// reason).
Exec select_exec(DeviceChoice choice, const CudaProbe& probe, int cpu_threads = 0);

// One line saying which backend a run uses and why, e.g. "backend: cuda (device 0: NVIDIA H100, sm_90)".
std::string describe_selection(const Exec& exec, const CudaProbe& probe);

// select_exec on this machine, making the chosen device current and logging the choice once per process.
Exec select_backend(DeviceChoice choice, int cpu_threads = 0);

// How this process's OpenMP threads wait, for the reports that say so (romp info, the backend line).
//
// libgomp's idle threads spin for a while before they sleep (OMP_WAIT_POLICY unset). On a machine shared
// with other work a spinning thread holds the core that the thread it waits for needs: the default scene
// took 6.2 s on 2 threads beside one busy process, against 3.2 s with OMP_WAIT_POLICY=passive and 3.7 s
// on one thread (the 2-core development machine). libgomp reads the variable once, in its constructor,
// before main() runs, so `romp` and `romp-bench` are launchers (cli/launcher.cpp) that set it, unless the
// user did, and start the program proper. Returns "passive (romp's default)", the user's OMP_WAIT_POLICY
// with "(OMP_WAIT_POLICY)", or "the OpenMP runtime's default" for a program started without the launcher.
std::string openmp_wait_policy();

}  // namespace romp
