// Per-particle and per-node math shared by the differentiable step's forward and adjoint kernels.
#pragma once

#include "kernels/diffmpm/dense_grid.h"
#include "kernels/diffmpm/diff_step.h"
#include "kernels/math/atomic_planes.h"
#include "kernels/math/mat3.h"
#include "kernels/mpm/bspline.h"
#include "kernels/mpm/domain_walls.h"
#include "kernels/mpm/mls_transfer.h"

namespace romp::diffmpm {

template <class T>
ROMP_HD_INLINE T inverse_dx(const StepParams<T>& step) {
  return T(1) / step.dx;
}

// D⁻¹ and the MLS stress factor k = −dt V₀ D⁻¹ (mpm::stress_factor) of this step.
template <class T>
ROMP_HD_INLINE T inverse_inertia(const StepParams<T>& step) {
  return mpm::inverse_inertia(inverse_dx(step));
}
template <class T>
ROMP_HD_INLINE T stress_factor(const StepParams<T>& step, const ParticleInputs<T>& in, Index p) {
  return mpm::stress_factor(step.dt, in.volume[p], inverse_inertia(step));
}

// The affine momentum a particle scatters: k P Fᵀ + m C (APIC plus the MLS internal force).
template <class T>
ROMP_HD_INLINE Mat3<T> particle_affine(const StepParams<T>& step, const ParticleInputs<T>& in, Index p) {
  return mpm::affine_momentum(stress_factor(step, in, p), in.P.load(p), in.F.load(p), in.mass[p], in.C.load(p));
}

// One of the 27 nodes of a particle's stencil: entry (i, j, k), its grid index, weight w and
// offset d = x_node − x_particle.
template <class T>
struct StencilNode {
  int i, j, k;
  Index index;
  T weight;
  Vec3<T> offset;
};

// Calls visit(StencilNode<T>) for each node of `stencil`: the loop every transfer and its adjoint run.
template <class T, class Visit>
ROMP_HD_INLINE void for_each_stencil_node(const StepParams<T>& step, const DenseGridView<T>& grid,
                                          const mpm::QuadraticStencil<T>& stencil, const Visit& visit) {
  mpm::for_each_stencil_offset([&](int i, int j, int k) {
    visit(StencilNode<T>{i, j, k, grid.index(stencil.base[0] + i, stencil.base[1] + j, stencil.base[2] + k),
                         stencil.weight(i, j, k), stencil.offset(i, j, k, step.dx)});
  });
}

// ∂w_ijk/∂x_p of the quadratic B-spline weights. Per axis, with f the offset from the base node in
// cells, w = ½(1.5 − f)², ¾ − (f − 1)², ½(f − 0.5)², so dw/df = f − 1.5, 2(1 − f), f − 0.5, and
// df/dx = 1/dx. The weights are C¹, so this gradient is continuous where the base node changes.
template <class T>
struct StencilGradient {
  T dw[3][3];  // dw[axis][k] / dx

  ROMP_HD StencilGradient(const mpm::QuadraticStencil<T>& stencil, T inverse_dx) {
    for (int a = 0; a < 3; ++a) {
      const T f = stencil.fx[a];
      dw[a][0] = (f - T(1.5)) * inverse_dx;
      dw[a][1] = T(2) * (T(1) - f) * inverse_dx;
      dw[a][2] = (f - T(0.5)) * inverse_dx;
    }
  }

  ROMP_HD Vec3<T> operator()(const mpm::QuadraticStencil<T>& s, const StencilNode<T>& node) const {
    const int i = node.i, j = node.j, k = node.k;
    return Vec3<T>(dw[0][i] * s.w[1][j] * s.w[2][k], s.w[0][i] * dw[1][j] * s.w[2][k],
                   s.w[0][i] * s.w[1][j] * dw[2][k]);
  }
};

// A massive node's velocity in the grid update: q_i / m_i, the free velocity (plus dt g) and the
// components the walls keep of it; the update's result is hadamard(kept, free), so its adjoint
// applies the same mask.
template <class T>
struct NodeUpdate {
  mpm::NodeVelocity<T> velocity;
  Vec3<T> kept;
};

template <class T>
ROMP_HD_INLINE NodeUpdate<T> node_update(const StepParams<T>& step, const DenseGridView<T>& grid, Index n) {
  int node[3];
  grid.coordinates(n, node);
  const Vec3<T> position(T(node[0]) * step.dx, T(node[1]) * step.dx, T(node[2]) * step.dx);
  const mpm::NodeVelocity<T> velocity(grid.momentum.load(n), T(1) / grid.mass[n], step.dt, step.gravity);
  return {velocity, mpm::wall_keep_mask(step.domain, position, step.dx, velocity.free)};
}

// The grid velocity gathered at a particle: v = Σ w v_i and C = D⁻¹ Σ w v_i (x_i − x_p)ᵀ (APIC).
template <class T>
struct GatheredVelocity {
  Vec3<T> v;
  Mat3<T> C;
};

template <class T>
ROMP_HD_INLINE GatheredVelocity<T> gather_velocity(const StepParams<T>& step, const DenseGridView<T>& grid,
                                                   const mpm::QuadraticStencil<T>& stencil) {
  mpm::VelocityGather<T> gathered;
  for_each_stencil_node(step, grid, stencil, [&](const StencilNode<T>& node) {
    gathered.add(node.weight, grid.velocity.load(node.index), node.offset);
  });
  return {gathered.v, gathered.C(inverse_inertia(step))};
}

}  // namespace romp::diffmpm
