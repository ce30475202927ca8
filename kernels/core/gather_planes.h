// GatherPlanes: the rows `index` of component-major planes, as a for_each functor; gather_arrays: the same
// rows of several arrays in one launch.
#pragma once

#include <cstdint>

#include "kernels/core/exec.h"
#include "kernels/core/hd.h"
#include "kernels/core/span.h"

namespace romp {

// destination[c destination_stride + to] = source[c source_stride + from] for each of `components` planes: one
// row of component-major planes copied. The loads go in batches ahead of their stores, in source order: ptxas may
// not move a plain load past a store that could alias it, so a plane-by-plane loop would keep one load in flight
// per thread (71 % of the H200's copy rate for a copy); a batch keeps kRowBatch (bench/results/gpu-notes.md). A
// short last batch loads its last plane again rather than branch around the loads.
template <class T>
ROMP_HD void copy_row(const T* source, Index source_stride, Index from, T* destination, Index destination_stride,
                      Index to, int components) {
  constexpr int kRowBatch = 4;
  ROMP_NO_UNROLL
  for (int first = 0; first < components; first += kRowBatch) {
    T values[kRowBatch];
    ROMP_UNROLL
    for (int k = 0; k < kRowBatch; ++k) {
      const int plane = first + k < components ? first + k : components - 1;
      values[k] = source[plane * source_stride + from];
    }
    ROMP_UNROLL
    for (int k = 0; k < kRowBatch; ++k) {
      if (first + k < components) destination[(first + k) * destination_stride + to] = values[k];
    }
  }
}

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
    copy_row(source.data(), source_count, index[i], destination.data(), index.size(), i, components);
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
