// memory suite: the copy bandwidth each backend reaches, the bound that memory-bound kernels are judged against.
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "bench/suites/suites.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/for_each.h"
#include "kernels/core/gather_planes.h"
#include "kernels/core/memory.h"
#include "kernels/core/read_only.h"

namespace romp::bench {
namespace {

// A copy as most element-wise functors are written: one element a thread, a plain load.
struct CopyKernel {
  Span<const float> source;
  Span<float> destination;
  ROMP_HD void operator()(Index i) const { destination[i] = source[i]; }
};

// A copy as a streaming functor is written for the GPU: read-only loads, four elements a CUDA thread.
struct StreamingCopyKernel {
  static constexpr int kItemsPerThread = 4;
  Span<const float> source;
  Span<float> destination;
  ROMP_HD void operator()(Index i) const { destination[i] = read_only(source, i); }
};

// The particles' float planes after a sort: kParticlePlanes planes gathered through an order (here the identity, as
// after a sort that moved no particle) by gather_arrays, whose row loop (copy_row) the sort's GatherParticle shares.
constexpr int kParticlePlanes = 26;

std::string place(const Exec& exec) { return exec.is_cuda() ? "cuda" : "cpu_threads=" + std::to_string(exec.threads); }

}  // namespace

void run_memory_suite(Context& context) {
  // 128 MiB per buffer at scale 1: far beyond the last-level cache of the CPUs and GPUs we measure.
  const Index n = context.scaled(Index(1) << 25, 1 << 16);
  constexpr double kBytesPerFloat = 2.0 * sizeof(float);  // one read, one write
  for (const Exec& exec : context.execs()) {
    DeviceBuffer<float> source(exec.backend, n);
    DeviceBuffer<float> destination(exec.backend, n);
    source.fill_zero(exec.stream);
    const CopyKernel kernel{source.span(), destination.span()};
    const Measurement& by_kernel = context.time(
        "memory", "for_each_copy<float>", exec, n, "float", [&] { for_each(exec, n, kernel); }, kBytesPerFloat);
    double best = by_kernel.gigabytes_per_second();
    const StreamingCopyKernel streaming{source.span(), destination.span()};
    const Measurement& by_streaming = context.time(
        "memory", "for_each_copy_streaming<float>", exec, n, "float", [&] { for_each(exec, n, streaming); },
        kBytesPerFloat);
    best = std::max(best, by_streaming.gigabytes_per_second());

    const Index rows = n / kParticlePlanes;
    std::vector<std::int32_t> identity(std::size_t(rows), 0);
    std::iota(identity.begin(), identity.end(), 0);
    const auto order = DeviceBuffer<std::int32_t>::from_host(exec.backend, identity);
    const GatheredArrays particle_planes =
        GatheredArrays().add(source.span().subspan(0, rows * kParticlePlanes),
                             destination.span().subspan(0, rows * kParticlePlanes), kParticlePlanes);
    context.time(
        "memory", "gather_rows<float x26>", exec, rows, "row",
        [&] { gather_arrays(exec, particle_planes, rows, order.span()); },
        kBytesPerFloat * kParticlePlanes + sizeof(std::int32_t));
    if (exec.is_cuda()) {
      const Measurement& by_runtime = context.time(
          "memory", "cudaMemcpy_d2d<float>", exec, n, "float",
          [&] {
        memory::copy(destination.data(), exec.backend, source.data(), exec.backend, destination.bytes(), exec.stream);
          },
          kBytesPerFloat);
      best = std::max(best, by_runtime.gigabytes_per_second());
    }
    context.record("memory." + place(exec) + ".copy_gbps", best);
  }
}

}  // namespace romp::bench
