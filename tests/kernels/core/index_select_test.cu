// IndexSelector: the indices of the flags equal to a value, in increasing order, on either backend.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/for_each.h"
#include "kernels/core/index_select.h"
#include "kernels/core/memory.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

TEST(IndexSelector, SelectsTheIndicesOfTheValueInIncreasingOrder) {
  const Exec& exec = test::exec();
  // Statuses 0, 1, 2 in an irregular pattern over more than one CUDA tile of items.
  std::vector<std::int32_t> flags(5000);
  for (std::size_t i = 0; i < flags.size(); ++i) flags[i] = std::int32_t((i * i + 3 * i) % 7 % 3);
  const DeviceBuffer<std::int32_t> device_flags =
      DeviceBuffer<std::int32_t>::from_host(exec.backend, flags, exec.stream);
  DeviceBuffer<std::int32_t> selected(exec.backend, Index(flags.size()));
  IndexSelector select;
  for (const std::int32_t value : {0, 2, 5}) {
    std::vector<std::int32_t> expected;
    for (std::size_t i = 0; i < flags.size(); ++i)
      if (flags[i] == value) expected.push_back(std::int32_t(i));
    const Index count = select(exec, device_flags.span(), value, selected.span());
    ASSERT_EQ(count, Index(expected.size())) << value;
    EXPECT_EQ(download(exec.backend, selected.prefix(count), exec.stream), expected) << value;
  }
}

// Called every substep: after the first call it allocates nothing and reads back only the count.
TEST(IndexSelector, RepeatedCallsAllocateNothingAndDownloadOnlyTheCount) {
  const Exec& exec = test::exec();
  const DeviceBuffer<std::int32_t> flags =
      DeviceBuffer<std::int32_t>::from_host(exec.backend, std::vector<std::int32_t>(300, 1), exec.stream);
  DeviceBuffer<std::int32_t> selected(exec.backend, 300);
  IndexSelector select;
  EXPECT_EQ(select(exec, flags.span(), 1, selected.span()), 300);
  const memory::Traffic before = memory::traffic();
  EXPECT_EQ(select(exec, flags.span().subspan(0, 200), 1, selected.span()), 200);
  const memory::Traffic after = memory::traffic();
  EXPECT_EQ(after.allocations, before.allocations);
  EXPECT_EQ(after.uploads, before.uploads);
  // The count comes back in one download, on the CPU as on CUDA, so CPU runs count what a GPU pays.
  EXPECT_EQ(after.downloads - before.downloads, 1);
}

// The count left on the device: the same selection, no round trip, and a launch over every flag that stops
// at the count (for_each_bounded) touches exactly the selected indices.
struct MarkSelected {
  Span<const std::int32_t> selected;
  Span<std::int32_t> marks;
  ROMP_HD void operator()(Index i) const { marks[selected[i]] += 1; }
};

TEST(IndexSelector, CountLeftOnTheDeviceBoundsALaunchWithoutARoundTrip) {
  const Exec& exec = test::exec();
  std::vector<std::int32_t> flags(3000);
  for (std::size_t i = 0; i < flags.size(); ++i) flags[i] = std::int32_t(i % 5 == 2);
  const DeviceBuffer<std::int32_t> device_flags = DeviceBuffer<std::int32_t>::from_host(exec.backend, flags);
  DeviceBuffer<std::int32_t> selected(exec.backend, Index(flags.size()));
  DeviceBuffer<std::int32_t> marks =
      DeviceBuffer<std::int32_t>::from_host(exec.backend, std::vector<std::int32_t>(flags.size()));
  IndexSelector select;
  select.select_on_device(exec, device_flags.span(), 1, selected.span());  // sizes CUB's storage
  const memory::Traffic before = memory::traffic();
  const Span<const std::int64_t> count = select.select_on_device(exec, device_flags.span(), 1, selected.span());
  for_each_bounded(exec, Index(flags.size()), count, MarkSelected{selected.span(), marks.span()});
  const memory::Traffic after = memory::traffic();
  EXPECT_EQ(after.downloads, before.downloads);
  EXPECT_EQ(after.allocations, before.allocations);
  EXPECT_EQ(download(exec.backend, count)[0], 600);
  EXPECT_EQ(marks.to_host(), flags);  // each selected index marked once, nothing else
}

TEST(IndexSelector, TooLittleRoomIsAnError) {
  const Exec& exec = test::exec();
  const DeviceBuffer<std::int32_t> flags(exec.backend, 10);
  DeviceBuffer<std::int32_t> selected(exec.backend, 9);
  IndexSelector select;
  EXPECT_THROW(select(exec, flags.span(), 0, selected.span()), Error);
}

}  // namespace
}  // namespace romp
