// Per-particle and per-node math shared by the differentiable step's forward and adjoint kernels.
#pragma once

#include "kernels/math/atomic_planes.h"
#include "kernels/diffmpm/dense_grid.h"
#include "kernels/diffmpm/diff_step.h"
#include "kernels/math/mat3.h"
#include "kernels/mpm/bspline.h"
#include "kernels/mpm/step.h"

namespace romp::diffmpm {

template <class T>
ROMP_HD_INLINE T inverse_dx(const StepParams<T>& step) { return T(1) / step.dx; }

// D⁻¹ of MLS-MPM for quadratic B-splines, 4 / dx² (Hu et al. 2018, Sec. 5.3).
template <class T>
ROMP_HD_INLINE T inverse_inertia(const StepParams<T>& step) {
  return T(mpm::kInverseInertiaScale) / (step.dx * step.dx);
}

// The stress factor k of the MLS affine impulse k P Fᵀ: -dt V₀ D⁻¹ (Hu et al. 2018, Eq. 16).
template <class T>
ROMP_HD_INLINE T stress_factor(const StepParams<T>& step, const ParticleInputs<T>& in, Index p) {
  return -step.dt * in.volume[p] * inverse_inertia(step);
}

// The affine momentum a particle scatters: k P Fᵀ + m C (APIC plus the MLS internal force).
template <class T>
ROMP_HD_INLINE Mat3<T> particle_affine(const StepParams<T>& step, const ParticleInputs<T>& in, Index p) {
  return stress_factor(step, in, p) * times_transpose(in.P.load(p), in.F.load(p)) + in.mass[p] * in.C.load(p);
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
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        visit(StencilNode<T>{i, j, k, grid.index(stencil.base[0] + i, stencil.base[1] + j, stencil.base[2] + k),
                             stencil.weight(i, j, k), stencil.offset(i, j, k, step.dx)});
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

// The velocity components a node keeps after the walls (1) or loses (0), given its velocity before
// them. Every wall rule is a per-component mask, so the grid update's adjoint applies the same mask.
// The rule is the engine's (mpm::update_grid with resolve_contact and zero friction).
template <class T>
ROMP_HD_INLINE Vec3<T> wall_mask(const StepParams<T>& step, const int node[3], const Vec3<T>& v) {
  Vec3<T> keep = Vec3<T>::constant(T(1));
  for (int a = 0; a < 3; ++a) {
    const bool low = node[a] < step.wall_cells;
    const bool high = node[a] > step.cells[a] - step.wall_cells;
    if (!low && !high) continue;
    if (step.walls == mpm::ContactType::Sticky) return Vec3<T>::zero();
    const bool approaching = (low && v[a] < T(0)) || (high && v[a] > T(0));
    if (step.walls == mpm::ContactType::Slip || approaching) keep[a] = T(0);
  }
  return keep;
}

// A massive node's velocity in the grid update: transferred q_i / m_i, free (plus dt g) and the
// wall mask of the free velocity; the update's result is hadamard(kept, free).
template <class T>
struct NodeVelocity {
  Vec3<T> transferred, free, kept;
};

template <class T>
ROMP_HD_INLINE NodeVelocity<T> node_velocity(const StepParams<T>& step, const DenseGridView<T>& grid, Index n) {
  int node[3];
  grid.coordinates(n, node);
  NodeVelocity<T> out;
  out.transferred = grid.momentum.load(n) * (T(1) / grid.mass[n]);
  out.free = out.transferred + step.dt * step.gravity;
  out.kept = wall_mask(step, node, out.free);
  return out;
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
  GatheredVelocity<T> out{Vec3<T>::zero(), Mat3<T>::zero()};
  for_each_stencil_node(step, grid, stencil, [&](const StencilNode<T>& node) {
    const Vec3<T> wv = node.weight * grid.velocity.load(node.index);
    out.v += wv;
    out.C += Mat3<T>::outer(wv, node.offset);
  });
  out.C *= inverse_inertia(step);
  return out;
}

// The engine keeps particles kDomainMarginCells inside the domain after G2P (mpm::grid_to_particle),
// so the stencil never leaves the grid; the differentiable step clamps the same way.
template <class T>
ROMP_HD_INLINE T low_position_bound(const StepParams<T>& step) {
  return T(mpm::kDomainMarginCells) * step.dx;
}
template <class T>
ROMP_HD_INLINE T high_position_bound(const StepParams<T>& step, int axis) {
  return (T(step.cells[axis]) - T(mpm::kDomainMarginCells)) * step.dx;
}

// Coordinate `axis` of a position clamped to the bounds. NaN (from a law gone non-finite) goes to the
// low bound: the next substep's stencil must index inside the grid whatever the laws did.
template <class T>
ROMP_HD_INLINE T clamp_to_domain(const StepParams<T>& step, T x, int axis) {
  const T low = low_position_bound(step);
  return math::select(x >= low, math::min(x, high_position_bound(step, axis)), low);
}

}  // namespace romp::diffmpm
