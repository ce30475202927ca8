// gather_planes: the GatherPlanes launch for callers compiled as C++.
#include "kernels/core/gather_planes.h"

#include "kernels/core/for_each.h"

namespace romp {

template <class T>
void gather_planes(const Exec& exec, Span<const T> source, Index source_count, int components,
                   Span<const std::int32_t> index, Span<T> destination, Span<const std::int64_t> count) {
  for_each_up_to(exec, index.size(), count, GatherPlanes<T>{source, source_count, destination, index, components});
}

template void gather_planes<float>(const Exec&, Span<const float>, Index, int, Span<const std::int32_t>, Span<float>,
                                   Span<const std::int64_t>);
template void gather_planes<std::int32_t>(const Exec&, Span<const std::int32_t>, Index, int, Span<const std::int32_t>,
                                          Span<std::int32_t>, Span<const std::int64_t>);

}  // namespace romp
