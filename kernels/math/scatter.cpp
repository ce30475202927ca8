// Scatter::for_exec: one CPU thread needs no atomics.
#include "kernels/math/scatter.h"

#include <omp.h>

namespace romp {

Scatter Scatter::for_exec(const Exec& exec) {
  Scatter scatter;
  scatter.serial_ = !exec.is_cuda() && (exec.threads == 1 || (exec.threads <= 0 && omp_get_max_threads() == 1));
  return scatter;
}

}  // namespace romp
