// The interpolation weights of a hexahedral particle domain, integrated in the reference configuration.
//
// Enriched MPM (Zhu et al., Sec. 4): a particle is the material region of a trilinear hexahedron
// with corners X_α. Quantities pass particle → corners → grid, with the particle-to-corner weights
// averaged over the undeformed domain Ω⁰ (Eq. 4–6):
//   ω_αp = (1/V⁰) ∫_Ω⁰ N_α dΩ,     g_αp = (1/V⁰) ∫_Ω⁰ ∇_X N_α dΩ,
// so that ω_ip = Σ_α ω_αp ω_i(x_α) and ∇_X ω_ip = Σ_α ω_i(x_α) g_αp. They depend on the reference
// shape only and are computed once, by 2×2×2 Gauss quadrature of the isoparametric map
// X(ξ) = Σ_α N_α(ξ) X_α, ξ ∈ [−1, 1]³ (exact for parallelepipeds, where det ∂X/∂ξ is constant).
// Corner α = 4a + 2b + c sits at ξ = (2a − 1, 2b − 1, 2c − 1).
#pragma once

#include "kernels/core/hd.h"
#include "kernels/material/volume.h"
#include "kernels/math/mat3.h"
#include "kernels/math/scalar.h"
#include "kernels/math/vec3.h"

namespace romp::mpm {

inline constexpr int kDomainCorners = 8;

template <class T>
ROMP_HD_INLINE Vec3<T> corner_reference_coordinates(int corner) {
  return Vec3<T>(T(2 * (corner >> 2) - 1), T(2 * ((corner >> 1) & 1) - 1), T(2 * (corner & 1) - 1));
}

// The trilinear shape function of corner α at ξ, N_α(ξ) = Π_a (1 + s_a ξ_a)/2 with s = the corner's
// reference coordinates, and its gradient with respect to ξ.
template <class T>
ROMP_HD_INLINE T corner_shape_function(int corner, const Vec3<T>& xi) {
  const Vec3<T> s = corner_reference_coordinates<T>(corner);
  return T(0.125) * (T(1) + s[0] * xi[0]) * (T(1) + s[1] * xi[1]) * (T(1) + s[2] * xi[2]);
}

template <class T>
ROMP_HD_INLINE Vec3<T> corner_shape_gradient(int corner, const Vec3<T>& xi) {
  const Vec3<T> s = corner_reference_coordinates<T>(corner);
  const T f0 = T(0.5) * (T(1) + s[0] * xi[0]), f1 = T(0.5) * (T(1) + s[1] * xi[1]), f2 = T(0.5) * (T(1) + s[2] * xi[2]);
  return Vec3<T>(T(0.5) * s[0] * f1 * f2, T(0.5) * s[1] * f0 * f2, T(0.5) * s[2] * f0 * f1);
}

template <class T>
struct HexDomainWeights {
  T volume;                          // V⁰ = ∫_Ω⁰ dΩ
  T weight[kDomainCorners];          // ω_αp: Σ_α ω_αp = 1
  Vec3<T> gradient[kDomainCorners];  // g_αp: Σ_α g_αp = 0 and Σ_α X_α g_αpᵀ = I
};

// The weights of the hexahedron with reference corners X[α]. Its Jacobian must be invertible at
// the Gauss points (a valid, non-inverted hexahedron); the caller builds domains from lattice cells.
template <class T>
ROMP_HD HexDomainWeights<T> hex_domain_weights(const Vec3<T> (&X)[kDomainCorners]) {
  HexDomainWeights<T> result{};
  const T gauss = T(1) / math::sqrt(T(3));
  for (int q = 0; q < kDomainCorners; ++q) {
    const Vec3<T> xi = gauss * corner_reference_coordinates<T>(q);
    T N[kDomainCorners];
    Vec3<T> dN_dxi[kDomainCorners];
    Mat3<T> J = Mat3<T>::zero();  // ∂X/∂ξ
    for (int a = 0; a < kDomainCorners; ++a) {
      N[a] = corner_shape_function(a, xi);
      dN_dxi[a] = corner_shape_gradient(a, xi);
      J += Mat3<T>::outer(X[a], dN_dxi[a]);
    }
    const T det_J = determinant(J);
    // ∇_X N = J⁻ᵀ ∇_ξ N, and J⁻ᵀ det J is the cofactor matrix: no division before the sum.
    const Mat3<T> cofactor_J = material::cofactor(J);
    result.volume += det_J;  // unit Gauss weights
    for (int a = 0; a < kDomainCorners; ++a) {
      result.weight[a] += N[a] * det_J;
      result.gradient[a] += cofactor_J * dN_dxi[a];
    }
  }
  const T inverse_volume = T(1) / result.volume;
  for (int a = 0; a < kDomainCorners; ++a) {
    result.weight[a] *= inverse_volume;
    result.gradient[a] *= inverse_volume;
  }
  return result;
}

}  // namespace romp::mpm
