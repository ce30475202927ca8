// Bounds: the axis-aligned box [low, high] that encloses a shape, in double precision on the host.
#pragma once

#include "kernels/math/vec3.h"

namespace romp::geometry {

struct Bounds {
  Vec3<double> low = Vec3<double>::zero();
  Vec3<double> high = Vec3<double>::zero();

  Vec3<double> size() const { return high - low; }
  Vec3<double> center() const { return 0.5 * (low + high); }
  bool contains(const Vec3<double>& p) const {
    for (int a = 0; a < 3; ++a)
      if (p[a] < low[a] || p[a] > high[a]) return false;
    return true;
  }
};

}  // namespace romp::geometry
