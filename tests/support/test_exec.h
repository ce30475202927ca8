// The Exec a backend-parameterised test runs on, chosen by the test binary's --backend flag.
#pragma once

#include "kernels/core/exec.h"

namespace romp::test {

// Exec::cpu() for `--backend=cpu` (the default) and `--backend=guarded`, Exec::cuda() for `--backend=cuda`. With
// --backend=cuda and no device, every test is skipped before it starts.
const Exec& exec();

// The same backend as exec() with a given CPU thread count (CUDA ignores it).
Exec exec_with_threads(int threads);

}  // namespace romp::test
