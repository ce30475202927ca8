// The MLS-MPM transfer arithmetic of one particle and one node (Hu et al. 2018, APIC with the MLS
// internal force), shared by the engine (float, sparse grid) and the differentiable step (float or
// double, dense grid): D⁻¹, the affine momentum a particle scatters, the momentum a node receives,
// the G2P gather and a node's velocity before the boundaries. Each kernel brings its own stencil loop.
#pragma once

#include "kernels/core/hd.h"
#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"
#include "kernels/mpm/bspline.h"

namespace romp::mpm {

// D⁻¹ of MLS-MPM for quadratic B-splines, kInverseInertiaScale / dx² (Hu et al. 2018, Sec. 5.3).
template <class T>
ROMP_HD_INLINE T inverse_inertia(T inverse_dx) {
  return T(kInverseInertiaScale) * inverse_dx * inverse_dx;
}

// The factor k of the MLS stress impulse k P Fᵀ: −dt V₀ D⁻¹ (Hu et al. 2018, Eq. 16).
template <class T>
ROMP_HD_INLINE T stress_factor(T dt, T volume, T inverse_inertia) {
  return -dt * volume * inverse_inertia;
}

// The MLS internal force as an affine impulse k P Fᵀ, applied through the same (x_i − x_p) moments as
// APIC's C. PIC/FLIP scatters this alone.
template <class T>
ROMP_HD_INLINE Mat3<T> stress_impulse(T k, const Mat3<T>& P, const Mat3<T>& F) {
  return k * times_transpose(P, F);
}

// The affine momentum A = k P Fᵀ + m C an APIC particle scatters.
template <class T>
ROMP_HD_INLINE Mat3<T> affine_momentum(T k, const Mat3<T>& P, const Mat3<T>& F, T mass, const Mat3<T>& C) {
  return stress_impulse(k, P, F) + mass * C;
}

// The momentum node i receives from a particle of momentum m v and affine momentum A:
// w (m v + A (x_i − x_p)), with offset = x_i − x_p.
template <class T>
ROMP_HD_INLINE Vec3<T> node_momentum(T weight, const Vec3<T>& momentum, const Mat3<T>& affine, const Vec3<T>& offset) {
  return weight * (momentum + affine * offset);
}

// What G2P gathers over a particle's stencil: v = Σ w v_i and B = Σ w v_i (x_i − x_p)ᵀ, whence
// C = D⁻¹ B, APIC's affine velocity and the MLS velocity gradient.
template <class T>
struct VelocityGather {
  Vec3<T> v = Vec3<T>::zero();
  Mat3<T> B = Mat3<T>::zero();

  ROMP_HD void add(T weight, const Vec3<T>& node_velocity, const Vec3<T>& offset) {
    const Vec3<T> wv = weight * node_velocity;
    v += wv;
    B += Mat3<T>::outer(wv, offset);
  }
  ROMP_HD Mat3<T> C(T inverse_inertia) const { return inverse_inertia * B; }
};

// A massive node's velocity in the grid update before the boundaries act: the transferred q_i / m_i,
// and that plus gravity over the substep (the free velocity).
template <class T>
struct NodeVelocity {
  Vec3<T> transferred;
  Vec3<T> free;

  ROMP_HD NodeVelocity(const Vec3<T>& momentum, T inverse_mass, T dt, const Vec3<T>& gravity)
      : transferred(momentum * inverse_mass), free(transferred + dt * gravity) {}
};

}  // namespace romp::mpm
