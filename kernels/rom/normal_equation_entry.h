// One entry of the projection's normal equations (see rom::normal_equations in reduced_dynamics.h), the
// functor behind it and behind the device Gauss–Newton of position_projection.cu.
#pragma once

#include "kernels/core/hd.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"

namespace romp::rom {

// One thread per entry of [A | c | ‖residual‖²]; each loops over the points in order. r² + r + 1
// threads suffice: the point count of a projection is the sample count, small by design.
struct NormalEquationEntry {
  int latent;
  Span<const float> J;
  Vec3Planes<const float> target, reference;
  Span<double> system;

  ROMP_HD double residual(int o, Index p) const {
    const double t = target.data()[o * target.count() + p];
    return reference.data() ? t - double(reference.data()[o * reference.count() + p]) : t;
  }

  ROMP_HD void operator()(Index entry) const {
    const Index m = target.count();
    const int r = latent;
    double sum = 0.0;
    if (entry < Index(r) * r) {
      const int a = int(entry / r), b = int(entry % r);
      for (Index p = 0; p < m; ++p)
        for (int o = 0; o < 3; ++o) sum += double(J[(o * r + a) * m + p]) * double(J[(o * r + b) * m + p]);
    } else if (entry < Index(r) * r + r) {
      const int a = int(entry - Index(r) * r);
      for (Index p = 0; p < m; ++p)
        for (int o = 0; o < 3; ++o) sum += double(J[(o * r + a) * m + p]) * residual(o, p);
    } else {
      for (Index p = 0; p < m; ++p)
        for (int o = 0; o < 3; ++o) sum += residual(o, p) * residual(o, p);
    }
    system[entry] = sum;
  }
};

}  // namespace romp::rom
