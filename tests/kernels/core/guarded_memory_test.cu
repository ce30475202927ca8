// Guarded mode: the CPU backend's buffers open to kernels and transfers only, and a touch from host
// code anywhere else crashes with a message naming guarded memory, as it would fail on a GPU.
#include <gtest/gtest.h>

#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/for_each.h"
#include "kernels/core/guarded_memory.h"

namespace romp {
namespace {

class GuardedMemory : public ::testing::Test {
 protected:
  void SetUp() override { memory::enable_guard(); }
};

struct Doubled {
  Span<float> values;
  ROMP_HD void operator()(Index i) const { values[i] *= 2.0f; }
};

TEST_F(GuardedMemory, KernelsAndTransfersReachTheBuffers) {
  DeviceBuffer<float> buffer = DeviceBuffer<float>::from_host(Backend::Cpu, std::vector<float>{1.0f, 2.0f, 3.0f});
  for_each(Exec::cpu(), buffer.size(), Doubled{buffer.span()});
  EXPECT_EQ(buffer.to_host(), (std::vector<float>{2.0f, 4.0f, 6.0f}));
  buffer.fill_zero();
  EXPECT_EQ(buffer.to_host(), (std::vector<float>{0.0f, 0.0f, 0.0f}));
  const DeviceBuffer<float> copy = buffer.clone();
  EXPECT_EQ(copy.to_host(), buffer.to_host());
}

TEST_F(GuardedMemory, HostCodeThatReadsABufferCrashesThere) {
  DeviceBuffer<float> buffer = DeviceBuffer<float>::from_host(Backend::Cpu, std::vector<float>{1.0f, 2.0f});
  EXPECT_DEATH(
      {
        volatile float read = buffer.data()[1];
        (void)read;
      },
      "host code touched device memory");
}

TEST_F(GuardedMemory, HostCodeThatWritesABufferCrashesThere) {
  DeviceBuffer<int> buffer(Backend::Cpu, 1000);
  EXPECT_DEATH({ buffer.data()[999] = 7; }, "host code touched device memory");
}

TEST_F(GuardedMemory, AccessEndsWithTheLaunch) {
  DeviceBuffer<float> buffer(Backend::Cpu, 4);
  buffer.fill_zero();
  {
    const memory::DeviceAccess open;
    const memory::DeviceAccess nested;  // nesting keeps the pages open until the outer one ends
  }
  EXPECT_DEATH(
      {
        volatile float read = buffer.data()[0];
        (void)read;
      },
      "host code touched device memory");
}

TEST_F(GuardedMemory, ReleasedBlocksAreReusedAndStayGuarded) {
  std::vector<const float*> first;
  for (int round = 0; round < 2; ++round) {
    std::vector<DeviceBuffer<float>> buffers;
    for (int b = 0; b < 8; ++b) buffers.emplace_back(Backend::Cpu, 10000);
    for (int b = 0; b < 8 && round == 0; ++b) first.push_back(buffers[std::size_t(b)].data());
    if (round == 1) {
      int reused = 0;
      for (const DeviceBuffer<float>& buffer : buffers)
        for (const float* earlier : first) reused += buffer.data() == earlier;
      EXPECT_EQ(reused, 8);
      EXPECT_DEATH(
          {
            volatile float read = buffers[3].data()[5];
            (void)read;
          },
          "host code touched device memory");
    }
  }
}

}  // namespace
}  // namespace romp
