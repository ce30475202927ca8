// The suites romp-bench can run; each lives in its own file under bench/suites/.
#pragma once

#include "bench/harness.h"

namespace romp::bench {

void run_memory_suite(Context& context);

}  // namespace romp::bench
