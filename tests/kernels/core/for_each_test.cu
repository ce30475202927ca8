// romp::for_each visits every index exactly once, on the backend the test binary was started with.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/fill.h"
#include "kernels/core/for_each.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

struct CountVisits {
  Span<int> visits;
  ROMP_HD void operator()(Index i) const { visits[i] += 1; }
};

struct WriteSquare {
  Span<double> out;
  ROMP_HD void operator()(Index i) const { out[i] = double(i) * double(i); }
};

// The same, declaring several elements a CUDA thread.
struct CountVisitsThreeAThread : CountVisits {
  static constexpr int kItemsPerThread = 3;
};

template <class Counter>
std::vector<int> visit_counts(const Exec& exec, Index n) {
  DeviceBuffer<int> visits(exec.backend, n);
  visits.fill_zero(exec.stream);
  for_each(exec, n, Counter{{visits.span()}});
  return visits.to_host(exec.stream);
}

TEST(ForEach, VisitsEveryIndexExactlyOnce) {
  static_assert(detail::kItemsPerThread<CountVisits> == 1 && detail::kItemsPerThread<CountVisitsThreeAThread> == 3);
  // Sizes around the CUDA block size and a tile of three blocks' worth, and far from any multiple of them.
  for (Index n : {Index(1), Index(255), Index(256), Index(257), Index(767), Index(768), Index(769), Index(100003)}) {
    for (const std::vector<int>& visits :
         {visit_counts<CountVisits>(test::exec(), n), visit_counts<CountVisitsThreeAThread>(test::exec(), n)}) {
      ASSERT_EQ(Index(visits.size()), n);
      for (Index i = 0; i < n; ++i) ASSERT_EQ(visits[i], 1) << "index " << i << " of " << n;
    }
  }
}

// What a CUDA launch of several elements a thread covers, on the host: its tiles take every element below n
// once, and the last tile is the only one that reaches past n.
TEST(ForEach, TilesOfSeveralElementsAThreadCoverEachElementOnce) {
  constexpr int kBlockSize = 4;
  for (const int items : {1, 3}) {
    for (const Index n : {Index(1), Index(11), Index(12), Index(13), Index(50)}) {
      std::vector<int> visits(std::size_t(n), 0);
      const Index tiles = detail::tile_count(n, kBlockSize, items);
      for (Index block = 0; block < tiles; ++block)
        for (int thread = 0; thread < kBlockSize; ++thread)
          for (int k = 0; k < items; ++k) {
            const Index element = detail::tile_element(block, thread, k, kBlockSize, items);
            ASSERT_GE(element, 0);
            if (element < n)
              ++visits[std::size_t(element)];
            else
              ASSERT_EQ(block, tiles - 1) << "element " << element << " of " << n;
          }
      for (Index i = 0; i < n; ++i) ASSERT_EQ(visits[std::size_t(i)], 1) << "index " << i << " of " << n;
    }
  }
}

// for_each's default CUDA block: the occupancy calculator's, unless the elements are too few to give every SM a
// block; whole warps, at least one.
TEST(ForEach, BlockSizeReachesEverySmBeforeTheOccupancyOptimum) {
  constexpr int kSms = 132;
  EXPECT_EQ(detail::block_size_for(1000000, 672, kSms), 672);  // enough elements: the optimum
  EXPECT_EQ(detail::block_size_for(1000, 672, kSms), 32);      // ⌈1000 / 132⌉ = 8: one warp a block, 32 SMs busy
  EXPECT_EQ(detail::block_size_for(13200, 672, kSms), 96);     // 100 an SM, rounded down to whole warps
  EXPECT_EQ(detail::block_size_for(13200, 64, kSms), 64);      // never above the optimum
  EXPECT_EQ(detail::block_size_for(1, 1024, kSms), 32);        // never below a warp
  // Every SM gets a block whenever the elements allow one a warp.
  for (const Index n : {Index(4225), Index(50000), Index(99999)}) {
    const int block = detail::block_size_for(n, 1024, kSms);
    EXPECT_EQ(block % 32, 0);
    EXPECT_GE((n + block - 1) / block, std::min<Index>(kSms, (n + 31) / 32)) << n;
  }
}

// The environment's fixed block size: empty or 0 leaves the choice to block_size_for; anything but whole warps up
// to 1024 is refused with the variable's name.
TEST(ForEach, BlockSizeFromTheEnvironmentIsWholeWarpsOrRefused) {
  EXPECT_EQ(detail::parse_block_size(nullptr), 0);
  EXPECT_EQ(detail::parse_block_size(""), 0);
  EXPECT_EQ(detail::parse_block_size("0"), 0);
  EXPECT_EQ(detail::parse_block_size("256"), 256);
  EXPECT_EQ(detail::parse_block_size("1024"), 1024);
  for (const char* bad : {"16", "100", "2048", "-32", "256 ", "many"}) {
    try {
      detail::parse_block_size(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("ROMP_FOR_EACH_BLOCK_SIZE"), std::string::npos) << error.what();
    }
  }
}

// A bounded launch runs the indices below its count, each once, however the count compares with the bound and
// with the blocks the device holds at once (CUDA loops over one resident wave in strides of the grid: a bound
// of millions is many strides).
TEST(ForEach, BoundedLaunchesVisitEachIndexBelowTheirCountOnce) {
  const Exec& exec = test::exec();
  constexpr Index kBound = 3000017;
  DeviceBuffer<int> visits(exec.backend, kBound);
  DeviceBuffer<std::int64_t> count(exec.backend, 1);
  for (const std::int64_t live : {std::int64_t(0), std::int64_t(1), std::int64_t(257), std::int64_t(2500001),
                                  std::int64_t(kBound), std::int64_t(kBound + 5)}) {
    visits.fill_zero(exec.stream);
    count.copy_from_host(Span<const std::int64_t>(&live, 1), exec.stream);
    for_each_bounded(exec, kBound, count.span(), CountVisits{visits.span()});
    const std::vector<int> host = visits.to_host(exec.stream);
    for (Index i = 0; i < kBound; ++i) ASSERT_EQ(host[i], i < live ? 1 : 0) << "index " << i << ", count " << live;
  }
  // No count: the whole bound.
  visits.fill_zero(exec.stream);
  for_each_bounded(exec, kBound, {}, CountVisits{visits.span()});
  const std::vector<int> host = visits.to_host(exec.stream);
  for (Index i = 0; i < kBound; ++i) ASSERT_EQ(host[i], 1) << "index " << i;
}

TEST(ForEach, ZeroElementsLaunchNothing) {
  // A null span would fault if the functor ran.
  for_each(test::exec(), 0, CountVisits{Span<int>()});
  synchronize(test::exec());
}

TEST(ForEach, SameResultForEveryCpuThreadCount) {
  constexpr Index n = 4099;
  for (int threads : {1, 2, 7}) {
    const Exec exec = test::exec_with_threads(threads);
    DeviceBuffer<double> out(exec.backend, n);
    for_each(exec, n, WriteSquare{out.span()});
    const std::vector<double> host = out.to_host(exec.stream);
    for (Index i = 0; i < n; ++i) ASSERT_EQ(host[i], double(i) * double(i)) << "threads " << threads;
  }
}

// fill() writes its value into exactly the span it is given, without a host transfer.
TEST(Fill, SetsEveryElementOfTheSpanAndNoOther) {
  const Exec& exec = test::exec();
  DeviceBuffer<std::int64_t> slots(exec.backend, 5);
  slots.fill_zero(exec.stream);
  const memory::Traffic before = memory::traffic();
  fill(exec, slots.span().subspan(1, 3), INT64_MAX);
  EXPECT_EQ(memory::traffic().uploads, before.uploads);
  EXPECT_EQ(slots.to_host(exec.stream), (std::vector<std::int64_t>{0, INT64_MAX, INT64_MAX, INT64_MAX, 0}));
}

}  // namespace
}  // namespace romp
