// gather_planes: the GatherPlanes launch for callers compiled as C++.
#include "kernels/core/gather_planes.h"

#include "kernels/core/for_each.h"

namespace romp {

template <class T>
void gather_planes(const Exec& exec, Span<const T> source, Index source_count, int components,
                   Span<const std::int32_t> index, Span<T> destination) {
  for_each(exec, index.size(), GatherPlanes<T>{source, source_count, destination, index, components});
}

template void gather_planes<float>(const Exec&, Span<const float>, Index, int, Span<const std::int32_t>, Span<float>);
template void gather_planes<std::int32_t>(const Exec&, Span<const std::int32_t>, Index, int, Span<const std::int32_t>,
                                          Span<std::int32_t>);

}  // namespace romp
