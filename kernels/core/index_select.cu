// IndexSelector: CUB's DeviceSelect::If over the indices on CUDA, a sequential loop on the CPU.
#include "kernels/core/index_select.h"

#include <climits>
#include <string>

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/core/guarded_memory.h"
#include "kernels/core/memory.h"

#if defined(__CUDACC__)
#include <thrust/iterator/counting_iterator.h>

#include <cub/device/device_select.cuh>

#include "kernels/core/cuda_check.h"
#endif

namespace romp {
namespace {

struct FlagEquals {
  const std::int32_t* flags;
  std::int32_t value;
  const std::int64_t* flag_count;  // null: every flag
  ROMP_HD bool operator()(std::int32_t i) const { return (!flag_count || i < *flag_count) && flags[i] == value; }
};

struct AddCount {
  Span<const std::int64_t> count;
  Span<std::int64_t> total;
  ROMP_HD void operator()(Index) const { total[0] += count[0]; }
};

}  // namespace

Index IndexSelector::operator()(const Exec& exec, Span<const std::int32_t> flags, std::int32_t value,
                                Span<std::int32_t> selected) {
  if (flags.empty()) return 0;
  // The count comes back as on the device, so host traffic counted on the CPU is the GPU's.
  return Index(download(exec.backend, select_on_device(exec, flags, value, selected), exec.stream)[0]);
}

Span<const std::int64_t> IndexSelector::select_on_device(const Exec& exec, Span<const std::int32_t> flags,
                                                         std::int32_t value, Span<std::int32_t> selected,
                                                         Span<const std::int64_t> flag_count) {
  const Index n = flags.size();
  ROMP_CHECK(selected.size() >= n, "IndexSelector: room for " + std::to_string(selected.size()) + " indices of " +
                                       std::to_string(n) + " flags");
  ROMP_CHECK(n <= INT32_MAX, "IndexSelector: indices are 32-bit, got " + std::to_string(n) + " flags");
  count_.ensure_size(exec.backend, 1);
  if (n == 0) {
    count_.fill_zero(exec.stream);
    return count_.prefix(1);
  }
  const FlagEquals equals{flags.data(), value, flag_count.empty() ? nullptr : flag_count.data()};
  if (exec.is_cuda()) {
#if defined(__CUDACC__)
    memory::note_launch();  // DeviceSelect
    const thrust::counting_iterator<std::int32_t> indices(0);
    std::size_t bytes = 0;
    ROMP_CUDA_CHECK(
        cub::DeviceSelect::If(nullptr, bytes, indices, selected.data(), count_.data(), n, equals, exec.stream));
    temporary_.ensure_size(exec.backend, Index(bytes));
    ROMP_CUDA_CHECK(cub::DeviceSelect::If(temporary_.data(), bytes, indices, selected.data(), count_.data(), n, equals,
                                          exec.stream));
    return count_.prefix(1);
#else
    throw Error("IndexSelector on CUDA from a translation unit not compiled by nvcc");
#endif
  }
  // The CPU's stand-in for DeviceSelect, one launch.
  memory::launch_on_cpu(exec.stream, 1, [n, equals, selected, count = count_.data()] {
    const memory::DeviceAccess launch;
    std::int32_t found = 0;
    for (Index i = 0; i < n; ++i)
      if (equals(std::int32_t(i))) selected[found++] = std::int32_t(i);
    count[0] = found;
  });
  return count_.prefix(1);
}

void add_count(const Exec& exec, Span<const std::int64_t> count, Span<std::int64_t> total) {
  ROMP_CHECK(count.size() >= 1 && total.size() >= 1, "add_count: a count and a total");
  for_each(exec, 1, AddCount{count, total});
}

}  // namespace romp
