// openmp_wait_policy: what the environment the OpenMP runtime started with says (openmp_waits.h).
#include "kernels/core/openmp_waits.h"

#include <cstdlib>

namespace romp {

std::string openmp_wait_policy() {
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  if (policy == nullptr) return "the OpenMP runtime's default";
  // The launcher marks the policy it chose, so a report can tell it from the user's.
  const char* chosen = std::getenv("ROMP_OPENMP_WAITS");
  return std::string(policy) + (chosen != nullptr ? " (romp's default)" : " (OMP_WAIT_POLICY)");
}

}  // namespace romp
