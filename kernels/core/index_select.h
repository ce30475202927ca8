// IndexSelector: the indices whose flag has a given value, compacted in increasing order, on the
// device (CUB's DeviceSelect on CUDA, a loop on the CPU: the same result on both).
#pragma once

#include <cstdint>

#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/core/span.h"

namespace romp {

// Keeps CUB's temporary storage and the count's slot, so that a loop selecting every step allocates
// only when its flags outgrow every earlier call.
class IndexSelector {
 public:
  // Writes the i < flags.size() with flags[i] == value into the front of `selected` (flags.size()
  // entries at least) and returns how many there are: one download, where compacting on the host
  // would download every flag and upload the indices.
  Index operator()(const Exec& exec, Span<const std::int32_t> flags, std::int32_t value, Span<std::int32_t> selected);
  // The same selection with its count left on exec's backend: the returned slot, valid until the next call,
  // for launches sized by flags.size() that stop at the count (for_each_bounded). No round trip. `flag_count`,
  // where given, is a count on the device: only the first flag_count[0] flags are read.
  Span<const std::int64_t> select_on_device(const Exec& exec, Span<const std::int32_t> flags, std::int32_t value,
                                            Span<std::int32_t> selected, Span<const std::int64_t> flag_count = {});

 private:
  DeviceBuffer<unsigned char> temporary_;
  DeviceBuffer<std::int64_t> count_;
};

// total[0] += count[0], both on exec's backend: a running total of counts that stay on the device (one launch).
void add_count(const Exec& exec, Span<const std::int64_t> count, Span<std::int64_t> total);

}  // namespace romp
