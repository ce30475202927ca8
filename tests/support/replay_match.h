// What a run replayed as CUDA graphs must give of the same run launched substep by substep: the same values bit
// for bit on the CPU (a replay runs the same loops in the same order), to rounding on CUDA (its P2G atomics sum in
// any order).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tests/support/test_exec.h"

namespace romp::test {

inline void expect_replay_matches(const std::vector<float>& replayed, const std::vector<float>& launched) {
  if (!exec().is_cuda()) {
    EXPECT_EQ(replayed, launched);
    return;
  }
  ASSERT_EQ(replayed.size(), launched.size());
  for (std::size_t j = 0; j < launched.size(); ++j)
    EXPECT_NEAR(replayed[j], launched[j], 1e-5f * (1.0f + std::fabs(launched[j]))) << "value " << j;
}

}  // namespace romp::test
