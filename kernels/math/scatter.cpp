// Scatter::for_exec: one CPU thread needs no atomics.
#include "kernels/math/scatter.h"

#include "kernels/core/for_each.h"

namespace romp {

Scatter Scatter::for_exec(const Exec& exec) {
  Scatter scatter;
  scatter.serial_ = !exec.is_cuda() && detail::cpu_threads(exec) == 1;
  return scatter;
}

}  // namespace romp
