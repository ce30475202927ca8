// gather_arrays: the rows `index` of float, int32 and uint64 arrays of several planes each, in one launch,
// and with a count on the device only its first rows.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/gather_planes.h"
#include "kernels/core/memory.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

TEST(GatherArrays, GathersTheRowsOfEveryArrayInOneLaunch) {
  const Exec& exec = test::exec();
  const Backend backend = exec.backend;
  // Four source rows; two planes of floats (row r: 10 r, 10 r + 1 in planes 0, 1), ints and keys of one.
  const auto floats = DeviceBuffer<float>::from_host(backend, {0, 10, 20, 30, 1, 11, 21, 31});
  const auto ints = DeviceBuffer<std::int32_t>::from_host(backend, {5, 6, 7, 8});
  const auto keys = DeviceBuffer<std::uint64_t>::from_host(backend, {100, 200, 300, 400});
  const auto index = DeviceBuffer<std::int32_t>::from_host(backend, {3, 0, 2});
  DeviceBuffer<float> float_rows(backend, 6);
  DeviceBuffer<std::int32_t> int_rows(backend, 3);
  DeviceBuffer<std::uint64_t> key_rows(backend, 3);
  GatheredArrays arrays;
  arrays.add(floats.span(), float_rows.span(), 2).add(ints.span(), int_rows.span(), 1);
  arrays.add(keys.span(), key_rows.span(), 1);
  const std::int64_t launches = memory::traffic().launches;
  gather_arrays(exec, arrays, 4, index.span());
  EXPECT_EQ(memory::traffic().launches - launches, 1);
  EXPECT_EQ(float_rows.to_host(), (std::vector<float>{30, 0, 20, 31, 1, 21}));
  EXPECT_EQ(int_rows.to_host(), (std::vector<std::int32_t>{8, 5, 7}));
  EXPECT_EQ(key_rows.to_host(), (std::vector<std::uint64_t>{400, 100, 300}));

  // With a count of 2 on the device, the third row stays as it was.
  const auto two = DeviceBuffer<std::int64_t>::from_host(backend, {2});
  int_rows.fill_zero();
  gather_arrays(exec, GatheredArrays().add(ints.span(), int_rows.span(), 1), 4, index.span(), two.span());
  EXPECT_EQ(int_rows.to_host(), (std::vector<std::int32_t>{8, 5, 0}));

  // An array shorter than its rows is refused.
  EXPECT_THROW(
      gather_arrays(exec, GatheredArrays().add(ints.span(), int_rows.span().subspan(0, 2), 1), 4, index.span()), Error);
}

// Arrays of more planes than a thread loads at once (copy_row's batches of four, the last one short): every plane
// of every row lands in its own place, the planes past the last batch's included.
TEST(GatherArrays, GathersArraysOfManyPlanes) {
  const Exec& exec = test::exec();
  constexpr Index kRows = 5;
  const std::vector<std::int32_t> rows = {4, 1, 1, 3};
  for (const int planes : {2, 4, 5, 11}) {
    std::vector<float> source(std::size_t(planes * kRows));
    for (int c = 0; c < planes; ++c)
      for (Index r = 0; r < kRows; ++r) source[std::size_t(c * kRows + r)] = float(100 * c + r);
    const auto floats = DeviceBuffer<float>::from_host(exec.backend, source);
    const auto index = DeviceBuffer<std::int32_t>::from_host(exec.backend, rows);
    const Index m = Index(rows.size());
    DeviceBuffer<float> gathered(exec.backend, planes * m);
    gathered.fill_zero(exec.stream);
    gather_arrays(exec, GatheredArrays().add(floats.span(), gathered.span(), planes), kRows, index.span());
    const std::vector<float> host = gathered.to_host(exec.stream);
    for (int c = 0; c < planes; ++c)
      for (Index i = 0; i < m; ++i)
        ASSERT_EQ(host[std::size_t(c * m + i)], float(100 * c + rows[std::size_t(i)]))
            << "plane " << c << " of " << planes << ", row " << i;
  }
}

}  // namespace
}  // namespace romp
