// PairSorter: CUB's DeviceRadixSort::SortPairs (stable) on CUDA, an index sort on the CPU.
#include "kernels/core/pair_sort.h"

#include <algorithm>
#include <numeric>
#include <vector>

#include "kernels/core/error.h"
#include "kernels/core/guarded_memory.h"
#include "kernels/core/memory.h"

#if defined(__CUDACC__)
#include <cub/device/device_radix_sort.cuh>

#include "kernels/core/cuda_check.h"
#endif

namespace romp {

std::pair<Span<const std::uint64_t>, Span<const std::int32_t>> PairSorter::operator()(const Exec& exec,
                                                                                      Span<const std::uint64_t> keys,
                                                                                      Span<const std::int32_t> values) {
  const Index n = keys.size();
  ROMP_CHECK(values.size() == n, "PairSorter: one value per key");
  keys_.ensure_size(exec.backend, n);
  values_.ensure_size(exec.backend, n);
  if (exec.is_cuda()) {
#if defined(__CUDACC__)
    memory::note_launch();  // DeviceRadixSort
    std::size_t bytes = 0;
    ROMP_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(nullptr, bytes, keys.data(), keys_.data(), values.data(),
                                                    values_.data(), n, 0, 64, exec.stream));
    temporary_.ensure_size(exec.backend, Index(bytes));
    ROMP_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(temporary_.data(), bytes, keys.data(), keys_.data(), values.data(),
                                                    values_.data(), n, 0, 64, exec.stream));
#else
    throw Error("PairSorter on CUDA from a translation unit not compiled by nvcc");
#endif
  } else {
    // The CPU's stand-in for the device sort, one launch.
    memory::launch_on_cpu(exec.stream, 1,
                          [n, keys, values, sorted_keys = keys_.data(), sorted_values = values_.data()] {
      const memory::DeviceAccess launch;
      std::vector<Index> order(static_cast<std::size_t>(n));
      std::iota(order.begin(), order.end(), Index(0));
      std::stable_sort(order.begin(), order.end(), [&keys](Index a, Index b) { return keys[a] < keys[b]; });
      for (Index i = 0; i < n; ++i) {
        sorted_keys[i] = keys[order[std::size_t(i)]];
        sorted_values[i] = values[order[std::size_t(i)]];
      }
    });
  }
  return {keys_.prefix(n), values_.prefix(n)};
}

}  // namespace romp
