// fill: the launch behind kernels/core/fill.h.
#include "kernels/core/fill.h"

#include <cstdint>

#include "kernels/core/for_each.h"

namespace romp {
namespace {

template <class T>
struct Fill {
  Span<T> values;
  T value;
  ROMP_HD void operator()(Index i) const { values[i] = value; }
};

}  // namespace

template <class T>
void fill(const Exec& exec, Span<T> values, T value) {
  for_each(exec, values.size(), Fill<T>{values, value});
}

template void fill<std::int64_t>(const Exec&, Span<std::int64_t>, std::int64_t);
template void fill<float>(const Exec&, Span<float>, float);

}  // namespace romp
