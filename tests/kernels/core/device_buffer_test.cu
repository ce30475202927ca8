// DeviceBuffer<T>: ownership moves, never copies implicitly; transfers round-trip exactly.
#include <gtest/gtest.h>

#include <numeric>
#include <type_traits>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/for_each.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

static_assert(!std::is_copy_constructible_v<DeviceBuffer<float>>, "copies must be explicit (clone)");
static_assert(!std::is_copy_assignable_v<DeviceBuffer<float>>, "copies must be explicit (clone)");
static_assert(std::is_nothrow_move_constructible_v<DeviceBuffer<float>>);
static_assert(std::is_nothrow_move_assignable_v<DeviceBuffer<float>>);

std::vector<float> ramp(Index n) {
  std::vector<float> values(n);
  std::iota(values.begin(), values.end(), -3.25f);
  return values;
}

struct Negate {
  Span<float> values;
  ROMP_HD void operator()(Index i) const { values[i] = -values[i]; }
};

TEST(DeviceBuffer, RoundTripsHostData) {
  const Exec& exec = test::exec();
  const std::vector<float> host = ramp(1000);
  const DeviceBuffer<float> buffer = DeviceBuffer<float>::from_host(exec.backend, host, exec.stream);
  EXPECT_EQ(buffer.backend(), exec.backend);
  EXPECT_EQ(buffer.size(), 1000);
  EXPECT_EQ(buffer.bytes(), 1000 * sizeof(float));
  EXPECT_EQ(buffer.to_host(exec.stream), host);
}

TEST(DeviceBuffer, MoveTransfersOwnershipAndEmptiesTheSource) {
  const Exec& exec = test::exec();
  DeviceBuffer<float> source = DeviceBuffer<float>::from_host(exec.backend, ramp(64), exec.stream);
  const float* storage = source.data();

  DeviceBuffer<float> moved(std::move(source));
  EXPECT_EQ(moved.data(), storage);
  EXPECT_EQ(moved.size(), 64);
  EXPECT_EQ(source.data(), nullptr);  // NOLINT(bugprone-use-after-move): the moved-from state is specified
  EXPECT_EQ(source.size(), 0);

  DeviceBuffer<float> assigned(exec.backend, 3);
  assigned = std::move(moved);
  EXPECT_EQ(assigned.data(), storage);
  EXPECT_EQ(moved.data(), nullptr);  // NOLINT(bugprone-use-after-move)
  EXPECT_EQ(assigned.to_host(exec.stream), ramp(64));
}

TEST(DeviceBuffer, CloneIsADeepCopy) {
  const Exec& exec = test::exec();
  DeviceBuffer<float> original = DeviceBuffer<float>::from_host(exec.backend, ramp(300), exec.stream);
  DeviceBuffer<float> copy = original.clone(exec.stream);
  EXPECT_NE(copy.data(), original.data());
  for_each(exec, copy.size(), Negate{copy.span()});
  EXPECT_EQ(original.to_host(exec.stream), ramp(300));
  EXPECT_EQ(copy.to_host(exec.stream)[0], 3.25f);
}

TEST(DeviceBuffer, CloneToTheCpuBringsDataHome) {
  const Exec& exec = test::exec();
  const DeviceBuffer<float> original = DeviceBuffer<float>::from_host(exec.backend, ramp(17), exec.stream);
  const DeviceBuffer<float> on_cpu = original.clone_to(Backend::Cpu, exec.stream);
  EXPECT_EQ(on_cpu.backend(), Backend::Cpu);
  EXPECT_EQ(std::vector<float>(on_cpu.data(), on_cpu.data() + 17), ramp(17));
}

TEST(DeviceBuffer, FillZeroClearsEveryByte) {
  const Exec& exec = test::exec();
  DeviceBuffer<double> buffer =
      DeviceBuffer<double>::from_host(exec.backend, std::vector<double>(513, 7.0), exec.stream);
  buffer.fill_zero(exec.stream);
  EXPECT_EQ(buffer.to_host(exec.stream), std::vector<double>(513, 0.0));
}

TEST(DeviceBuffer, EmptyBufferOwnsNothing) {
  DeviceBuffer<int> buffer(test::exec().backend, 0);
  EXPECT_TRUE(buffer.empty());
  EXPECT_EQ(buffer.data(), nullptr);
  EXPECT_TRUE(buffer.to_host().empty());
}

TEST(DeviceBuffer, TransferSizeMismatchIsAnError) {
  DeviceBuffer<float> buffer(test::exec().backend, 4);
  const std::vector<float> three(3, 1.0f);
  EXPECT_THROW(buffer.copy_from_host(Span<const float>(three.data(), 3)), Error);
}

// A buffer refilled every step with a varying count allocates only when the count outgrows it, and
// then with headroom; prefixes carry this step's elements.
TEST(DeviceBuffer, EnsureSizeGrowsWithHeadroomAndOtherwiseKeepsTheStorage) {
  const Exec& exec = test::exec();
  DeviceBuffer<float> buffer;
  buffer.ensure_size(exec.backend, 100);
  EXPECT_EQ(buffer.backend(), exec.backend);
  EXPECT_EQ(buffer.size(), 125);
  const float* storage = buffer.data();
  const memory::Traffic before = memory::traffic();
  for (const Index n : {60, 125, 1, 0}) {
    buffer.ensure_size(exec.backend, n);
    EXPECT_EQ(buffer.data(), storage) << n;
  }
  EXPECT_EQ(memory::traffic().allocations, before.allocations);
  buffer.ensure_size(exec.backend, 126);
  EXPECT_EQ(buffer.size(), 157);
  EXPECT_EQ(memory::traffic().allocations, before.allocations + 1);
}

TEST(DeviceBuffer, PrefixTransfersMoveOnlyThatPrefix) {
  const Exec& exec = test::exec();
  DeviceBuffer<float> buffer = DeviceBuffer<float>::from_host(exec.backend, std::vector<float>(10, 9.0f), exec.stream);
  const std::vector<float> four = ramp(4);
  upload(exec.backend, buffer.prefix(4), Span<const float>(four.data(), 4), exec.stream);
  EXPECT_EQ(download(exec.backend, buffer.prefix(4), exec.stream), four);
  EXPECT_EQ(download(exec.backend, buffer.span().subspan(4, 1), exec.stream), std::vector<float>{9.0f});
  EXPECT_THROW(buffer.prefix(11), Error);
  EXPECT_THROW(buffer.prefix(-1), Error);
  EXPECT_THROW(upload(exec.backend, buffer.prefix(3), Span<const float>(four.data(), 4), exec.stream), Error);
}

// upload_front: this step's values at the front, the buffer grown (with headroom) only when they outgrow it.
TEST(DeviceBuffer, UploadFrontGrowsOnlyWhenTheValuesOutgrowIt) {
  const Exec& exec = test::exec();
  DeviceBuffer<float> buffer;
  EXPECT_EQ(download(exec.backend, buffer.upload_front(exec.backend, ramp(8), exec.stream), exec.stream), ramp(8));
  EXPECT_EQ(buffer.size(), 10);
  const memory::Traffic before = memory::traffic();
  const Span<float> front = buffer.upload_front(exec.backend, ramp(3), exec.stream);
  EXPECT_EQ(front.size(), 3);
  EXPECT_EQ(download(exec.backend, front, exec.stream), ramp(3));
  EXPECT_TRUE(buffer.upload_front(exec.backend, std::vector<float>(), exec.stream).empty());
  const memory::Traffic after = memory::traffic();
  EXPECT_EQ(after.allocations, before.allocations);
  EXPECT_EQ(after.uploads - before.uploads, 1);  // the empty upload costs nothing
  buffer.upload_front(exec.backend, ramp(11), exec.stream);
  EXPECT_EQ(buffer.size(), 13);
}

// Uploads and downloads are counted on either backend (a round trip each on CUDA); empty ones cost
// nothing and are not.
TEST(DeviceBuffer, TransfersAreCounted) {
  const Exec& exec = test::exec();
  DeviceBuffer<float> buffer(exec.backend, 8);
  const std::vector<float> eight = ramp(8);
  const memory::Traffic before = memory::traffic();
  buffer.copy_from_host(Span<const float>(eight.data(), 8), exec.stream);
  upload(exec.backend, buffer.prefix(0), Span<const float>(), exec.stream);
  (void)buffer.to_host(exec.stream);
  (void)download(exec.backend, buffer.prefix(2), exec.stream);
  const memory::Traffic after = memory::traffic();
  EXPECT_EQ(after.uploads - before.uploads, 1);
  EXPECT_EQ(after.downloads - before.downloads, 2);
  EXPECT_EQ(after.allocations, before.allocations);
}

TEST(DeviceBuffer, NegativeSizeIsAnError) { EXPECT_THROW(DeviceBuffer<float>(test::exec().backend, -1), Error); }

}  // namespace
}  // namespace romp
