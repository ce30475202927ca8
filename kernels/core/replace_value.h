// ReplaceValue: a for_each functor that rewrites every entry equal to `from` as `to` (e.g. releasing
// the particles of a Dirichlet group). Launch it from a .cu file, as every for_each.
#pragma once

#include "kernels/core/hd.h"
#include "kernels/core/span.h"

namespace romp {

template <class T>
struct ReplaceValue {
  Span<T> values;
  T from, to;
  ROMP_HD void operator()(Index i) const {
    if (values[i] == from) values[i] = to;
  }
};

}  // namespace romp
