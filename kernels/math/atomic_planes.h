// Atomic adds of a vector into structure-of-arrays planes: the scatters into grid nodes and domain corners.
#pragma once

#include "kernels/core/atomic.h"
#include "kernels/core/hd.h"
#include "kernels/math/mat3_planes.h"

namespace romp {

template <class T>
ROMP_HD_INLINE void atomic_add(const Vec3Planes<T>& planes, Index i, const Vec3<T>& value) {
  for (int a = 0; a < 3; ++a) atomic_add(&planes.data()[a * planes.count() + i], value[a]);
}

}  // namespace romp
