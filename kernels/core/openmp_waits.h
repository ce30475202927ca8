// How this process's OpenMP threads wait, for the reports that say so (romp info, the backend line).
//
// libgomp's idle threads spin for a while before they sleep (OMP_WAIT_POLICY unset). On a machine shared
// with other work a spinning thread holds the core that the thread it waits for needs: the default scene
// took 6.2 s on 2 threads beside one busy process, against 3.2 s with OMP_WAIT_POLICY=passive and 3.7 s
// on one thread (the 2-core development machine). libgomp reads the variable once, in its constructor,
// before main() runs, so `romp` and `romp-bench` are launchers (host/cli/launcher.cpp) that set it, unless
// the user did, and start the program proper.
#pragma once

#include <string>

namespace romp {

// "passive (romp's default)", the user's OMP_WAIT_POLICY with "(OMP_WAIT_POLICY)", or "the OpenMP
// runtime's default" where the program was started without the launcher and the variable.
std::string openmp_wait_policy();

}  // namespace romp
