// The quadratic B-spline stencil of a particle: the 3x3x3 grid nodes it exchanges with, and their weights.
#pragma once

#include "kernels/core/hd.h"
#include "kernels/math/vec3.h"

namespace romp::mpm {

// For quadratic B-splines the MLS-MPM inertia-like tensor is D = dx^2/4 I (Hu et al. 2018, Sec. 5.3),
// so D^-1 = kInverseInertiaScale / dx^2.
inline constexpr float kInverseInertiaScale = 4.0f;

template <class T>
struct QuadraticStencil {
  int base[3];  // index of the lowest node touched, per axis
  T fx[3];      // particle position relative to the base node, in cells (in [0.5, 1.5))
  T w[3][3];    // w[axis][k]: 1D weight of node base + k

  // The lowest node touched along an axis by a particle at `cell` (its coordinate in cells). Truncation is
  // floor(cell - 0.5) because the engine keeps particles at least one cell inside the domain [0, L]^3 (see
  // kDomainMarginCells in domain_walls.h).
  ROMP_HD static int base_node(T cell) { return int(cell - T(0.5)); }

  ROMP_HD QuadraticStencil(const Vec3<T>& x, T inverse_dx) {
    for (int a = 0; a < 3; ++a) {
      const T cell = x[a] * inverse_dx;
      base[a] = base_node(cell);
      fx[a] = cell - T(base[a]);
      const T d0 = T(1.5) - fx[a], d1 = fx[a] - T(1), d2 = fx[a] - T(0.5);
      w[a][0] = T(0.5) * d0 * d0;
      w[a][1] = T(0.75) - d1 * d1;
      w[a][2] = T(0.5) * d2 * d2;
    }
  }

  ROMP_HD T weight(int i, int j, int k) const { return w[0][i] * w[1][j] * w[2][k]; }
  // x_node - x_particle, in metres.
  ROMP_HD Vec3<T> offset(int i, int j, int k, T dx) const {
    return Vec3<T>((T(i) - fx[0]) * dx, (T(j) - fx[1]) * dx, (T(k) - fx[2]) * dx);
  }
};

// visit(i, j, k) for the 27 nodes of a quadratic stencil, unrolled on the device: constant offsets pick the
// weights and the nodes' blocks from registers (loops the compiler kept rolled indexed them at run time, which
// put the stencil in local memory: a 56–128-byte stack frame in every transfer kernel).
template <class Visit>
ROMP_HD_INLINE void for_each_stencil_offset(const Visit& visit) {
  ROMP_UNROLL
  for (int i = 0; i < 3; ++i) {
    ROMP_UNROLL
    for (int j = 0; j < 3; ++j) {
      ROMP_UNROLL
      for (int k = 0; k < 3; ++k) visit(i, j, k);
    }
  }
}

}  // namespace romp::mpm
