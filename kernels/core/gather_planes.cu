// gather_arrays: one launch gathering the same rows of several arrays, for callers compiled as C++.
#include "kernels/core/gather_planes.h"

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"

namespace romp {
namespace {

struct GatherArrays {
  GatheredArrays arrays;
  Index source_count;
  Span<const std::int32_t> index;

  template <class T>
  ROMP_HD void gather(const GatheredPlanes<T>* planes, int count, Index i, Index row) const {
    for (int a = 0; a < count; ++a)
      copy_row(planes[a].source.data(), source_count, row, planes[a].destination.data(), index.size(), i,
               planes[a].components);
  }
  ROMP_HD void operator()(Index i) const {
    const Index row = index[i];
    gather(arrays.floats, arrays.float_count, i, row);
    gather(arrays.ints, arrays.int_count, i, row);
    gather(arrays.keys, arrays.key_count, i, row);
  }
};

template <class T>
void add_planes(GatheredPlanes<T>* planes, int& count, Span<const T> source, Span<T> destination, int components) {
  ROMP_CHECK(count < GatheredArrays::kMost, "gather_arrays: at most GatheredArrays::kMost arrays of each type");
  ROMP_CHECK(components >= 1, "gather_arrays: an array has at least one plane");
  planes[count++] = {source, destination, components};
}

}  // namespace

GatheredArrays& GatheredArrays::add(Span<const float> source, Span<float> destination, int components) {
  add_planes(floats, float_count, source, destination, components);
  return *this;
}

GatheredArrays& GatheredArrays::add(Span<const std::int32_t> source, Span<std::int32_t> destination, int components) {
  add_planes(ints, int_count, source, destination, components);
  return *this;
}

GatheredArrays& GatheredArrays::add(Span<const std::uint64_t> source, Span<std::uint64_t> destination, int components) {
  add_planes(keys, key_count, source, destination, components);
  return *this;
}

void gather_arrays(const Exec& exec, const GatheredArrays& arrays, Index source_count, Span<const std::int32_t> index,
                   Span<const std::int64_t> count) {
  const Index m = index.size();
  auto check = [&](const auto& planes) {
    ROMP_CHECK(
        planes.source.size() >= planes.components * source_count && planes.destination.size() >= planes.components * m,
        "gather_arrays: an array holds fewer rows than the source count or the index");
  };
  for (int a = 0; a < arrays.float_count; ++a) check(arrays.floats[a]);
  for (int a = 0; a < arrays.int_count; ++a) check(arrays.ints[a]);
  for (int a = 0; a < arrays.key_count; ++a) check(arrays.keys[a]);
  for_each_bounded(exec, m, count, GatherArrays{arrays, source_count, index});
}

}  // namespace romp
