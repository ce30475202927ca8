// The level-1 vector operations of kernels/core/vector_ops.h on the test binary's backend: element-wise
// updates exactly, and dot products accurate to double accumulation and independent of the thread count.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/vector_ops.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

std::vector<float> random_vector(Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> x(n);
  for (float& value : x) value = u(rng);
  return x;
}

TEST(VectorOps, ElementwiseUpdates) {
  const Exec& exec = test::exec();
  // Less than one CUDA tile (four elements a thread, 256 threads), and whole tiles with a partial one.
  for (const Index n : {Index(1000), Index(5003)}) {
    const std::vector<float> x = random_vector(n, 1), y0 = random_vector(n, 2);
    const DeviceBuffer<float> x_buffer = DeviceBuffer<float>::from_host(exec.backend, x, exec.stream);
    DeviceBuffer<float> y = DeviceBuffer<float>::from_host(exec.backend, y0, exec.stream);

    axpy(exec, 0.5f, x_buffer.span(), y.span());
    std::vector<float> result = y.to_host(exec.stream);
    for (Index k = 0; k < n; ++k) ASSERT_EQ(result[k], y0[k] + 0.5f * x[k]) << k << " of " << n;

    y.copy_from_host(Span<const float>(y0.data(), n), exec.stream);
    xpby(exec, x_buffer.span(), -2.0f, y.span());
    result = y.to_host(exec.stream);
    for (Index k = 0; k < n; ++k) ASSERT_EQ(result[k], x[k] + -2.0f * y0[k]) << k << " of " << n;
  }
}

TEST(VectorOps, DotIsAccurateAndIndependentOfTheThreadCount) {
  // More elements than lanes, and a count that is no multiple of them.
  const Index n = 3 * DotProduct::kLanes + 123;
  const std::vector<float> a = random_vector(n, 4), b = random_vector(n, 5);
  double expected = 0.0;
  for (Index k = 0; k < n; ++k) expected += double(a[k]) * double(b[k]);
  std::vector<double> results;
  for (int threads : {1, 2, 3}) {
    const Exec exec = test::exec_with_threads(threads);
    const DeviceBuffer<float> a_buffer = DeviceBuffer<float>::from_host(exec.backend, a, exec.stream);
    const DeviceBuffer<float> b_buffer = DeviceBuffer<float>::from_host(exec.backend, b, exec.stream);
    DotProduct dot(exec.backend);
    results.push_back(dot(exec, a_buffer.span(), b_buffer.span()));
  }
  EXPECT_NEAR(results[0], expected, 1e-12 * n);
  EXPECT_EQ(results[1], results[0]);
  EXPECT_EQ(results[2], results[0]);
}

}  // namespace
}  // namespace romp
