// The suites romp-bench can run; each lives in its own file under bench/suites/.
#pragma once

#include "bench/harness.h"

namespace romp::bench {

void run_memory_suite(Context& context);
void run_step_suite(Context& context);
// 3x3 SVDs per second: romp against Eigen (CPU) and cuSOLVER (GPU); needs memory first for the bandwidth fraction.
void run_svd_suite(Context& context);
// Seconds per neural-law training epoch (1000 substeps forward and backward, 1000 particles).
void run_train_suite(Context& context);

}  // namespace romp::bench
