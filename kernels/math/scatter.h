// Scatter: how a kernel adds into arrays that several of its loop iterations write (grid nodes, domain
// corners, the implicit solve's entries). Wherever iterations can run concurrently the adds are
// atomic; a CPU loop on one thread adds plainly. x86 has no atomic float add, so each atomic one is a
// lock-prefixed compare-and-swap loop that also stalls the pipeline: measured with perf on a
// one-thread run of the domain transfers (romp-bench stability, enriched cases), the compare-and-swaps
// took about 70 % of corners_to_grid. A one-thread loop adds in the same order either way, so both
// give the same bits there. On the GPU the adds are always atomic.
#pragma once

#include "kernels/core/exec.h"
#include "kernels/core/hd.h"
#include "kernels/math/atomic_planes.h"

namespace romp {

class Scatter {
 public:
  // Plain adds where `exec` runs each parallel loop on one CPU thread, atomic ones otherwise.
  static Scatter for_exec(const Exec& exec);

  template <class T>
  ROMP_HD_INLINE void add(T* address, T value) const {
#if defined(__CUDA_ARCH__)
    atomic_add(address, value);
#else
    if (serial_)
      *address += value;
    else
      atomic_add(address, value);
#endif
  }

  template <class T>
  ROMP_HD_INLINE void add(const Vec3Planes<T>& planes, Index i, const Vec3<T>& value) const {
    for (int a = 0; a < 3; ++a) add(&planes.data()[a * planes.count() + i], value[a]);
  }

  bool serial() const { return serial_; }

 private:
  bool serial_ = false;
};

}  // namespace romp
