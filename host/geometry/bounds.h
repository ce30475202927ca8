// Bounds: the axis-aligned box [low, high] that encloses a shape, in double precision on the host.
#pragma once

#include <cmath>
#include <vector>

#include "kernels/core/hd.h"
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

// The box of n points stored as three planes (every x, then every y, then every z), as ParticleInit
// holds positions.
inline Bounds bounds_of_planes(const std::vector<float>& planes, Index n) {
  Bounds box;
  box.low = Vec3<double>::constant(INFINITY);
  box.high = Vec3<double>::constant(-INFINITY);
  for (int a = 0; a < 3; ++a)
    for (Index p = 0; p < n; ++p) {
      const double value = planes[std::size_t(a * n + p)];
      box.low[a] = std::fmin(box.low[a], value);
      box.high[a] = std::fmax(box.high[a], value);
    }
  return box;
}

}  // namespace romp::geometry
