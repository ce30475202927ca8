// memory suite: the copy bandwidth each backend reaches, the bound that memory-bound kernels are judged against.
#include <algorithm>
#include <string>

#include "bench/suites/suites.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/for_each.h"
#include "kernels/core/memory.h"

namespace romp::bench {
namespace {

struct CopyKernel {
  Span<const float> source;
  Span<float> destination;
  ROMP_HD void operator()(Index i) const { destination[i] = source[i]; }
};

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
