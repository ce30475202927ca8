// The host's vectorisable e^x and erf (kernels/math/exp_erf.h) against the standard library: their stated
// accuracy over the ranges the neural laws' GELU meets, the exact values the laws rely on, and the clamp.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "kernels/math/exp_erf.h"

namespace romp::math {
namespace {

TEST(ExpErf, ExpIsWithinTwoUlpsOverTheFloatRange) {
  double worst = 0.0;
  for (float x = -87.0f; x <= 88.0f; x += 1.0e-3f) {
    const double expected = std::exp(double(x));
    worst = std::max(worst, std::abs(double(exp(x)) - expected) / expected);
  }
  EXPECT_LE(worst, 2.0 * std::numeric_limits<float>::epsilon()) << worst;
  EXPECT_EQ(exp(0.0f), 1.0f);
}

TEST(ExpErf, ExpClampsInsteadOfOverflowing) {
  EXPECT_EQ(exp(-1000.0f), exp(-87.0f));
  EXPECT_EQ(exp(1000.0f), exp(88.0f));
  EXPECT_TRUE(std::isfinite(exp(1000.0f)));
  EXPECT_GT(exp(-1000.0f), 0.0f);
}

TEST(ExpErf, ErfIsWithinItsAbsoluteBoundAndOdd) {
  double worst = 0.0;
  for (float x = -8.0f; x <= 8.0f; x += 1.0e-4f) {
    worst = std::max(worst, std::abs(double(erf(x)) - std::erf(double(x))));
    ASSERT_EQ(erf(-x), -erf(x)) << x;
  }
  // Abramowitz & Stegun 7.1.26 promise 1.5e-7; float rounding of its terms adds up to 1e-7 (worst measured:
  // 2.48e-7 at x = 0.84, compiled without FMA).
  EXPECT_LE(worst, 3e-7) << worst;
  EXPECT_EQ(erf(20.0f), 1.0f);
  EXPECT_EQ(erf(0.0f), 0.0f);
}

TEST(ExpErf, DoubleIsTheStandardLibrarys) {
  for (double x : {-3.0, -0.5, 0.0, 1e-8, 0.7, 2.5}) {
    EXPECT_EQ(exp(x), std::exp(x));
    EXPECT_EQ(erf(x), std::erf(x));
  }
}

}  // namespace
}  // namespace romp::math
