// Atomics under contention: many threads adding into few addresses, and min/max races.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "kernels/core/atomic.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/for_each.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

constexpr Index kAdds = 1 << 20;  // contributions
constexpr Index kBins = 7;        // addresses they land on (prime, so bins get unequal counts)

template <class T>
struct AddIntoBins {
  Span<T> bins;
  ROMP_HD T value(Index i) const { return T(i % 13) + T(1); }
  ROMP_HD void operator()(Index i) const { atomic_add(&bins[i % kBins], value(i)); }
};

template <class T>
struct AddQuartersIntoBins {
  Span<T> bins;
  // Multiples of 1/4: every partial sum (< 2^18) is exact in float, so any lost update shows.
  ROMP_HD T value(Index i) const { return T(0.25) * T(i % 10 + 1); }
  ROMP_HD void operator()(Index i) const { atomic_add(&bins[i % kBins], value(i)); }
};

template <class T>
struct AddTenthsIntoBins {
  Span<T> bins;
  // Not exactly representable, so the sum depends on the order of the additions.
  ROMP_HD T value(Index i) const { return T(0.1) * T(i % 10 + 1); }
  ROMP_HD void operator()(Index i) const { atomic_add(&bins[i % kBins], value(i)); }
};

template <class T>
struct MinMaxOfSequence {
  Span<T> extremes;  // [0] = min, [1] = max
  // A scrambled sequence with both signs; its min and max are known from the formula.
  ROMP_HD T value(Index i) const { return T((i * 7919) % 100003) - T(50000); }
  ROMP_HD void operator()(Index i) const {
    atomic_min(&extremes[0], value(i));
    atomic_max(&extremes[1], value(i));
  }
};

template <class T>
class AtomicInteger : public ::testing::Test {};
using IntegerTypes = ::testing::Types<std::int32_t, std::uint32_t, std::int64_t, std::uint64_t>;
TYPED_TEST_SUITE(AtomicInteger, IntegerTypes);

TYPED_TEST(AtomicInteger, ContendedAddsGiveExactSums) {
  using T = TypeParam;
  const Exec& exec = test::exec();
  DeviceBuffer<T> bins(exec.backend, kBins);
  bins.fill_zero(exec.stream);
  const AddIntoBins<T> kernel{bins.span()};
  for_each(exec, kAdds, kernel);
  std::vector<T> expected(kBins, T(0));
  for (Index i = 0; i < kAdds; ++i) expected[i % kBins] += kernel.value(i);
  EXPECT_EQ(bins.to_host(exec.stream), expected);
}

template <class T>
class AtomicFloat : public ::testing::Test {};
using FloatTypes = ::testing::Types<float, double>;
TYPED_TEST_SUITE(AtomicFloat, FloatTypes);

template <class T, class Kernel>
std::pair<std::vector<T>, std::vector<long double>> contended_float_sums(const Exec& exec) {
  DeviceBuffer<T> bins(exec.backend, kBins);
  bins.fill_zero(exec.stream);
  const Kernel kernel{bins.span()};
  for_each(exec, kAdds, kernel);
  std::vector<long double> exact(kBins, 0.0L);
  for (Index i = 0; i < kAdds; ++i) exact[i % kBins] += kernel.value(i);
  return {bins.to_host(exec.stream), exact};
}

TYPED_TEST(AtomicFloat, ContendedAddsLoseNoUpdate) {
  using T = TypeParam;
  const auto [sums, exact] = contended_float_sums<T, AddQuartersIntoBins<T>>(test::exec());
  for (Index b = 0; b < kBins; ++b) EXPECT_EQ((long double)sums[b], exact[b]) << "bin " << b;
}

TYPED_TEST(AtomicFloat, ContendedAddsMatchTheSumWithinRounding) {
  using T = TypeParam;
  const auto [sums, exact] = contended_float_sums<T, AddTenthsIntoBins<T>>(test::exec());
  const Index per_bin = (kAdds + kBins - 1) / kBins;
  for (Index b = 0; b < kBins; ++b) {
    // Recursive summation of k positive terms in any order errs by at most (k - 1) eps times the sum.
    const long double bound = (long double)(per_bin - 1) * std::numeric_limits<T>::epsilon() * exact[b];
    EXPECT_NEAR((long double)sums[b], exact[b], bound) << "bin " << b;
  }
}

template <class T>
class AtomicMinMax : public ::testing::Test {};
using MinMaxTypes = ::testing::Types<std::int32_t, std::int64_t, float, double>;
TYPED_TEST_SUITE(AtomicMinMax, MinMaxTypes);

TYPED_TEST(AtomicMinMax, RacingUpdatesKeepTheExtremes) {
  using T = TypeParam;
  const Exec& exec = test::exec();
  const std::vector<T> start{std::numeric_limits<T>::max(), std::numeric_limits<T>::lowest()};
  DeviceBuffer<T> extremes = DeviceBuffer<T>::from_host(exec.backend, start, exec.stream);
  const MinMaxOfSequence<T> kernel{extremes.span()};
  for_each(exec, kAdds, kernel);
  T lo = start[0], hi = start[1];
  for (Index i = 0; i < kAdds; ++i) {
    lo = std::min(lo, kernel.value(i));
    hi = std::max(hi, kernel.value(i));
  }
  const std::vector<T> result = extremes.to_host(exec.stream);
  EXPECT_EQ(result[0], lo);
  EXPECT_EQ(result[1], hi);
}

struct ClaimSlots {
  Span<std::uint64_t> slots;
  Span<std::int32_t> wins;
  ROMP_HD void operator()(Index i) const {
    const std::uint64_t mine = std::uint64_t(i) + 1;  // 0 marks a free slot
    if (atomic_cas(&slots[i % kBins], 0, mine) == 0) atomic_add(&wins[i % kBins], std::int32_t(1));
  }
};

TEST(AtomicCas, ExactlyOneClaimWinsEachSlot) {
  const Exec& exec = test::exec();
  DeviceBuffer<std::uint64_t> slots(exec.backend, kBins);
  DeviceBuffer<std::int32_t> wins(exec.backend, kBins);
  slots.fill_zero(exec.stream);
  wins.fill_zero(exec.stream);
  for_each(exec, kAdds, ClaimSlots{slots.span(), wins.span()});
  const std::vector<std::uint64_t> owners = slots.to_host(exec.stream);
  EXPECT_EQ(wins.to_host(exec.stream), std::vector<std::int32_t>(kBins, 1));
  for (Index b = 0; b < kBins; ++b) {
    ASSERT_NE(owners[b], 0u);
    EXPECT_EQ(Index(owners[b] - 1) % kBins, b) << "slot " << b << " holds a claim meant for another slot";
  }
}

TEST(Atomic, ReturnsThePreviousValue) {
  // Host-side semantics, the same contract as CUDA's atomicAdd/atomicMin/atomicMax.
  float f = 1.5f;
  EXPECT_EQ(atomic_add(&f, 2.0f), 1.5f);
  EXPECT_EQ(f, 3.5f);
  EXPECT_EQ(atomic_min(&f, 5.0f), 3.5f);
  EXPECT_EQ(f, 3.5f);
  EXPECT_EQ(atomic_max(&f, 5.0f), 3.5f);
  EXPECT_EQ(f, 5.0f);
  std::int64_t k = -4;
  EXPECT_EQ(atomic_add(&k, std::int64_t(10)), -4);
  EXPECT_EQ(atomic_min(&k, std::int64_t(-9)), 6);
  EXPECT_EQ(k, -9);
}

}  // namespace
}  // namespace romp
