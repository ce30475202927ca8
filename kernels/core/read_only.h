// read_only(values, i): element i of a span that no thread writes during the launch, read on CUDA through the
// read-only data path (ld.global.nc); a plain read on the host.
//
// Why: ptxas may not issue a plain load ahead of an earlier store that could alias it, so a thread that runs a
// light functor for several elements (kItemsPerThread, for_each.h) would wait for each element's load in turn.
// A read-only load carries no such order: the thread's loads go out together (checked in the SASS of the memory
// suite's copy, bench/results/gpu-notes.md), which is what a copy needs to approach the device's bandwidth.
#pragma once

#include "kernels/core/hd.h"
#include "kernels/core/span.h"

namespace romp {

template <class T>
ROMP_HD T read_only(Span<const T> values, Index i) {
#if defined(__CUDA_ARCH__)
  return __ldg(values.data() + i);
#else
  return values[i];
#endif
}

}  // namespace romp
