// Random point sets for the grid tests: n points in [lo, hi)^3, as three planes.
#pragma once

#include <random>
#include <vector>

#include "kernels/core/exec.h"

namespace romp::test {

inline std::vector<float> random_planes(Index n, float lo, float hi, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<float> x(3 * n);
  for (float& value : x) value = u(rng);
  return x;
}

}  // namespace romp::test
