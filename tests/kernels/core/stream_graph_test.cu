// StreamGraph: launches captured once and replayed, reading device memory as it is at each replay and the
// arguments as they were at capture, on either backend; what a graph cannot hold is refused.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/core/guarded_memory.h"
#include "kernels/core/index_select.h"
#include "kernels/core/memory.h"
#include "kernels/core/pair_sort.h"
#include "kernels/core/stream_graph.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

// x[i] += scale * (1 + step[0]): `scale` is an argument, `step` a value in device memory.
struct AddStep {
  Span<float> x;
  Span<const float> step;
  float scale;
  ROMP_HD void operator()(Index i) const { x[i] += scale * (1.0f + step[0]); }
};

template <class T>
void put(const Exec& exec, DeviceBuffer<T>& buffer, const std::vector<T>& host) {
  buffer.copy_from_host(Span<const T>(host.data(), Index(host.size())), exec.stream);
}

struct GraphTest : ::testing::Test {
  OwnedStream stream{test::exec().backend};
  Exec exec = with_capturable_stream(test::exec(), stream);
};

TEST_F(GraphTest, ReplaysReadDeviceMemoryAsItIsThenAndArgumentsAsTheyWereAtCapture) {
  constexpr Index n = 1000;
  DeviceBuffer<float> x(exec.backend, n), step(exec.backend, 1);
  x.fill_zero(exec.stream);
  float scale = 2.0f;
  StreamGraph graph;
  EXPECT_TRUE(graph.empty());
  graph.capture(exec, [&] { for_each(exec, n, AddStep{x.span(), step.span(), scale}); });
  EXPECT_FALSE(graph.empty());
  EXPECT_EQ(graph.launches(), 1);
  // The capture ran nothing.
  EXPECT_EQ(x.to_host(exec.stream), std::vector<float>(n, 0.0f));

  scale = 7.0f;  // too late for the graph: its launch keeps 2
  put(exec, step, {1.0f});
  graph.replay(exec);
  EXPECT_EQ(x.to_host(exec.stream), std::vector<float>(n, 4.0f));
  put(exec, step, {4.0f});
  graph.replay(exec);
  EXPECT_EQ(x.to_host(exec.stream), std::vector<float>(n, 14.0f));
}

// A replay is one launch for the host, whatever the graph holds; the capture launches nothing.
TEST_F(GraphTest, AReplayIsOneLaunch) {
  DeviceBuffer<float> x(exec.backend, 64), step(exec.backend, 1);
  x.fill_zero(exec.stream);
  step.fill_zero(exec.stream);
  StreamGraph graph;
  const memory::Traffic before = memory::traffic();
  graph.capture(exec, [&] {
    for (int k = 0; k < 5; ++k) for_each(exec, 64, AddStep{x.span(), step.span(), 1.0f});
    x.fill_zero(exec.stream);
    for_each(exec, 64, AddStep{x.span(), step.span(), 3.0f});
  });
  EXPECT_EQ(graph.launches(), 7);
  const memory::Traffic captured = memory::traffic();
  EXPECT_EQ(captured.launches, before.launches);
  EXPECT_EQ(captured.allocations, before.allocations);
  graph.replay(exec);
  graph.replay(exec);
  EXPECT_EQ(memory::traffic().launches - captured.launches, 2);
  EXPECT_EQ(x.to_host(exec.stream), std::vector<float>(64, 3.0f));
}

// The device primitives a substep uses are recorded like for_each: a sort, a selection with its count on the
// device, and launches over a bound that stop at that count.
struct CopyIndex {
  Span<const std::int32_t> from;
  Span<std::int32_t> to;
  ROMP_HD void operator()(Index i) const { to[i] = from[i]; }
};

TEST_F(GraphTest, RecordsSortsSelectionsAndLaunchesUpToADeviceCount) {
  constexpr Index n = 300;
  std::vector<std::int32_t> flags_host(n, 0);
  DeviceBuffer<std::int32_t> flags(exec.backend, n), selected(exec.backend, n), copied(exec.backend, n);
  DeviceBuffer<std::uint64_t> keys(exec.backend, n);
  std::vector<std::uint64_t> keys_host(n);
  for (Index i = 0; i < n; ++i) keys_host[std::size_t(i)] = std::uint64_t((i * 37) % n);
  put(exec, keys, keys_host);
  IndexSelector select;
  PairSorter sort;
  // Once eagerly: their scratch is allocated outside the capture.
  put(exec, flags, flags_host);
  select.select_on_device(exec, flags.span(), 1, selected.span());
  sort(exec, keys.span(), flags.span());
  copied.fill_zero(exec.stream);

  StreamGraph graph;
  Span<const std::int32_t> sorted_values;
  graph.capture(exec, [&] {
    const Span<const std::int64_t> count = select.select_on_device(exec, flags.span(), 1, selected.span());
    for_each_bounded(exec, n, count, CopyIndex{selected.span(), copied.span()});
    sorted_values = sort(exec, keys.span(), flags.span()).second;
  });
  EXPECT_EQ(graph.launches(), 3);

  for (const Index every : {3, 7}) {
    std::vector<std::int32_t> expected;
    for (Index i = 0; i < n; ++i) {
      flags_host[std::size_t(i)] = i % every == 0;
      if (i % every == 0) expected.push_back(std::int32_t(i));
    }
    put(exec, flags, flags_host);
    graph.replay(exec);
    const std::vector<std::int32_t> got = copied.to_host(exec.stream);
    EXPECT_EQ(std::vector<std::int32_t>(got.begin(), got.begin() + Index(expected.size())), expected) << every;
    // The pairs sorted by key: key k came from the i with i * 37 = k (mod n), whose flag the value is.
    const std::vector<std::int32_t> values = download(exec.backend, sorted_values, exec.stream);
    for (Index k = 0; k < n; ++k) {
      Index i = 0;
      while ((i * 37) % n != k) ++i;
      ASSERT_EQ(values[std::size_t(k)], flags_host[std::size_t(i)]) << k;
    }
  }
}

// What needs the host between launches cannot be part of a graph: refused by name, with the capture closed
// and the graph left empty, so that the next capture works.
TEST_F(GraphTest, RefusesAllocationsTransfersAndHostReadsOfDeviceMemory) {
  DeviceBuffer<float> x(exec.backend, 8), step(exec.backend, 1);
  step.fill_zero(exec.stream);
  const std::vector<float> host(8, 1.0f);
  const auto refused = [&](const std::function<void()>& enqueue, const std::string& what) {
    StreamGraph graph;
    try {
      graph.capture(exec, enqueue);
      ADD_FAILURE() << what << " was captured";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(what + " while a graph is being captured"), std::string::npos)
          << error.what();
    }
    EXPECT_TRUE(graph.empty());
    EXPECT_EQ(memory::open_capture(), nullptr);
  };
  refused([&] { DeviceBuffer<float> more(exec.backend, 16); }, "an allocation of 64 bytes");
  refused([&] { put(exec, x, host); }, "an upload of 32 bytes");
  refused([&] { (void)x.to_host(exec.stream); }, "a download of 32 bytes");
  refused([&] { synchronize(exec); }, "a wait for the device");
  if (!exec.is_cuda()) {
    // On the CPU a host read of device memory would go unnoticed, and read a value the graph has not computed.
    const auto read_device = [&] {
      const memory::DeviceAccess read;
      (void)x.data()[0];
    };
    refused(read_device, "a host touch of device memory");
    // CUDA refuses a launch on another stream inside a capture; the CPU's streams are tokens, refused alike.
    StreamGraph other;
    EXPECT_THROW(other.capture(exec, [&] { for_each(test::exec(), 8, AddStep{x.span(), step.span(), 1.0f}); }), Error);
    EXPECT_TRUE(other.empty());
  }
  StreamGraph graph;
  graph.capture(exec, [&] { for_each(exec, 8, AddStep{x.span(), step.span(), 1.0f}); });
  x.fill_zero(exec.stream);
  graph.replay(exec);
  EXPECT_EQ(x.to_host(exec.stream), std::vector<float>(8, 1.0f));
  EXPECT_THROW(StreamGraph().replay(exec), Error);
}

}  // namespace
}  // namespace romp
