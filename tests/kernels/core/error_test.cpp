// Error macros report the place and the failed expression; CUDA failures carry the runtime's words.
#include <gtest/gtest.h>

#include <string>

#include "kernels/core/error.h"
#include "kernels/core/span.h"

#if defined(ROMP_WITH_CUDA)
#include "kernels/core/cuda_check.h"
#endif

namespace romp {
namespace {

TEST(RompCheck, ThrowsWithFileLineAndExpression) {
  const int particles = -1;
  const int line = __LINE__ + 2;
  try {
    ROMP_CHECK(particles >= 0, "particle count must be non-negative");
    FAIL() << "ROMP_CHECK did not throw";
  } catch (const Error& error) {
    EXPECT_NE(error.file().find("error_test.cpp"), std::string::npos);
    EXPECT_EQ(error.line(), line);
    EXPECT_EQ(error.expression(), "particles >= 0");
    const std::string what = error.what();
    EXPECT_NE(what.find("particle count must be non-negative"), std::string::npos);
    EXPECT_NE(what.find("error_test.cpp:" + std::to_string(line)), std::string::npos);
  }
}

TEST(RompCheck, PassingConditionDoesNotEvaluateTheMessage) {
  int evaluated = 0;
  auto message = [&] {
    ++evaluated;
    return std::string("unused");
  };
  ROMP_CHECK(true, message());
  EXPECT_EQ(evaluated, 0);
}

#if defined(ROMP_WITH_CUDA)
TEST(RompCudaCheck, ThrowsWithTheRuntimeErrorName) {
  try {
    ROMP_CUDA_CHECK(cudaErrorInvalidValue);
    FAIL() << "ROMP_CUDA_CHECK did not throw";
  } catch (const Error& error) {
    EXPECT_EQ(error.expression(), "cudaErrorInvalidValue");
    EXPECT_NE(std::string(error.what()).find("cudaErrorInvalidValue"), std::string::npos);
  }
}

TEST(RompCudaCheck, SuccessDoesNotThrow) { EXPECT_NO_THROW(ROMP_CUDA_CHECK(cudaSuccess)); }
#endif

}  // namespace
}  // namespace romp
