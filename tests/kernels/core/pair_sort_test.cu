// PairSorter: keys in increasing order, pairs with equal keys in their input order, on either backend.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/pair_sort.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

TEST(PairSorter, SortsByKeyKeepingTheInputOrderOfEqualKeys) {
  const Exec& exec = test::exec();
  std::mt19937_64 random(11);
  // Few distinct keys (many ties), across the whole 64-bit range including its top bit.
  const std::vector<std::uint64_t> distinct = {UINT64_MAX, 0, 1ull << 63, 42, (1ull << 42) | 7};
  std::vector<std::uint64_t> keys(3000);
  for (std::uint64_t& key : keys) key = distinct[random() % distinct.size()];
  std::vector<std::int32_t> values(keys.size());
  std::iota(values.begin(), values.end(), 0);
  const auto device_keys = DeviceBuffer<std::uint64_t>::from_host(exec.backend, keys, exec.stream);
  const auto device_values = DeviceBuffer<std::int32_t>::from_host(exec.backend, values, exec.stream);
  PairSorter sort;
  for (int repeat = 0; repeat < 2; ++repeat) {  // reusing the sorter's storage
    const auto [sorted_keys, sorted_values] = sort(exec, device_keys.span(), device_values.span());
    const std::vector<std::uint64_t> got_keys = download(exec.backend, sorted_keys, exec.stream);
    const std::vector<std::int32_t> got_values = download(exec.backend, sorted_values, exec.stream);
    std::vector<std::int32_t> expected = values;
    std::stable_sort(expected.begin(), expected.end(),
                     [&](std::int32_t a, std::int32_t b) { return keys[a] < keys[b]; });
    ASSERT_EQ(got_values, expected);
    for (std::size_t i = 0; i < keys.size(); ++i) ASSERT_EQ(got_keys[i], keys[std::size_t(expected[i])]) << i;
  }
}

}  // namespace
}  // namespace romp
