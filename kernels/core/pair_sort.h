// PairSorter: (key, value) pairs sorted by key, stably, on exec's backend: CUB's radix sort on CUDA,
// std::stable_sort on the CPU. A stable sort's order is unique, so both give the same result.
#pragma once

#include <cstdint>
#include <utility>

#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/core/span.h"

namespace romp {

// Keeps its output and CUB's temporary storage between calls, so that a loop sorting every step
// allocates only when its pairs outgrow every earlier call.
class PairSorter {
 public:
  // The n pairs (keys[i], values[i]) in increasing key order, pairs with equal keys in their input
  // order; views of storage kept here, valid until the next call.
  std::pair<Span<const std::uint64_t>, Span<const std::int32_t>> operator()(const Exec& exec,
                                                                            Span<const std::uint64_t> keys,
                                                                            Span<const std::int32_t> values);

 private:
  DeviceBuffer<std::uint64_t> keys_;
  DeviceBuffer<std::int32_t> values_;
  DeviceBuffer<unsigned char> temporary_;
};

}  // namespace romp
