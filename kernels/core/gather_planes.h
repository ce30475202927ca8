// GatherPlanes: the rows `index` of component-major planes, as a for_each functor.
#pragma once

#include <cstdint>

#include "kernels/core/exec.h"
#include "kernels/core/hd.h"
#include "kernels/core/span.h"

namespace romp {

// destination[c m + i] = source[c n + index[i]] for i < m and each of `components` planes, where n is
// `source_count` and m = index.size() (the destination's plane stride).
template <class T>
struct GatherPlanes {
  Span<const T> source;
  Index source_count;
  Span<T> destination;
  Span<const std::int32_t> index;
  int components;
  ROMP_HD void operator()(Index i) const {
    const Index m = index.size();
    for (int c = 0; c < components; ++c) destination[c * m + i] = source[c * source_count + index[i]];
  }
};

// GatherPlanes launched on exec's backend, for host code compiled as C++ (a launch on CUDA must come
// from a file nvcc compiles). Instantiated for float and std::int32_t. `count`, where given, is a value on
// exec's backend: only the first count[0] of the index.size() rows are gathered (for_each_up_to).
template <class T>
void gather_planes(const Exec& exec, Span<const T> source, Index source_count, int components,
                   Span<const std::int32_t> index, Span<T> destination, Span<const std::int64_t> count = {});

}  // namespace romp
