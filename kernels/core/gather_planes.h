// GatherPlanes: the rows `index` of component-major planes, as a for_each functor; gather_arrays: the same
// rows of several arrays in one launch.
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

// The same rows of several arrays, float, int32 and uint64, in one launch (a gather per array would be a launch
// each): thread i copies row index[i] of every array. Each array has the source's row count and the
// index's, component-major.
template <class T>
struct GatheredPlanes {
  Span<const T> source;
  Span<T> destination;
  int components = 1;
};
struct GatheredArrays {
  static constexpr int kMost = 6;
  GatheredPlanes<float> floats[kMost];
  GatheredPlanes<std::int32_t> ints[kMost];
  GatheredPlanes<std::uint64_t> keys[kMost];
  int float_count = 0, int_count = 0, key_count = 0;

  GatheredArrays& add(Span<const float> source, Span<float> destination, int components);
  GatheredArrays& add(Span<const std::int32_t> source, Span<std::int32_t> destination, int components);
  GatheredArrays& add(Span<const std::uint64_t> source, Span<std::uint64_t> destination, int components);
};

// Rows `index` of every array of `arrays` (each holding source_count rows), into index.size() rows; with
// `count`, a value on exec's backend, only the first count[0] of them (for_each_bounded).
void gather_arrays(const Exec& exec, const GatheredArrays& arrays, Index source_count, Span<const std::int32_t> index,
                   Span<const std::int64_t> count = {});

}  // namespace romp
