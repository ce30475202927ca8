// Hencky (logarithmic) strain of the principal stretches, and St. Venant-Kirchhoff elasticity in it.
//
// The Hencky strain of F = U Σ Vᵀ is ε = log Σ (principal values). HenckyStVK is the quadratic
// energy in ε, ψ̂ = μ tr(ε²) + λ/2 (tr ε)², whose Kirchhoff stress τ̂ = 2μ ε + λ tr(ε) 1 is linear in
// ε (Klár et al. 2016, "Drucker-Prager elastoplasticity for sand animation"); it is the elastic
// part of the sand (DruckerPrager) and plasticine (VonMises) models, which share the helpers here.
//
// Clamp. The logarithm of a stretch σ ≤ 0 (an inverted or collapsed element) is undefined, so every
// stretch is first clamped to kMinHenckyStretch: ψ, P and the return maps are those of the clamped
// stretch. This follows the clamped-SVD inversion handling of Zhu et al. (Dynamically Enriched MPM,
// which clamps at 0.1): below the clamp the stress stays that of the clamped stretch, so it is
// bounded and still pushes the element back open. Below the clamp P is therefore not ∂ψ/∂F (which
// would vanish in the clamped direction and leave the element no restoring force), and the
// differential is the exact derivative of that P.
#pragma once

#include <cmath>

#include "kernels/core/hd.h"
#include "kernels/material/isotropic.h"
#include "kernels/math/mat3.h"
#include "kernels/math/scalar.h"
#include "kernels/math/vec3.h"

namespace romp::material {

// Smallest stretch a Hencky-based model takes the logarithm of: compression to 1/10⁴ of the rest
// length, far beyond what a physical simulation reaches, yet above the float SVD's absolute
// accuracy (about 1e-7 σ₀), so that a clamped stretch is never SVD round-off. Its Hencky strain is
// log(1e-4) ≈ −9.2 and its 1/σ is 1e4, which bounds |P̂| by about 3·10⁵ (μ + λ): finite in float.
template <class T>
inline constexpr T kMinHenckyStretch = T(1e-4);

template <class T>
ROMP_HD_INLINE Vec3<T> clamped_stretch(const Vec3<T>& sigma) {
  return Vec3<T>(math::max(sigma[0], kMinHenckyStretch<T>), math::max(sigma[1], kMinHenckyStretch<T>),
                 math::max(sigma[2], kMinHenckyStretch<T>));
}

// ε = log max(σ, kMinHenckyStretch), component-wise.
template <class T>
ROMP_HD_INLINE Vec3<T> hencky_strain(const Vec3<T>& sigma) {
  const Vec3<T> stretch = clamped_stretch(sigma);
  return Vec3<T>(std::log(stretch[0]), std::log(stretch[1]), std::log(stretch[2]));
}

// F = U exp(ε) Vᵀ: the deformation gradient with principal frame (U, V) and Hencky strain ε.
template <class T>
ROMP_HD_INLINE Mat3<T> from_hencky_strain(const Svd3<T>& svd, const Vec3<T>& strain) {
  return from_principal(svd.U, Vec3<T>(std::exp(strain[0]), std::exp(strain[1]), std::exp(strain[2])), svd.V);
}

template <class T>
ROMP_HD_INLINE T trace(const Vec3<T>& principal) {
  return principal[0] + principal[1] + principal[2];
}

// ε̂ = ε − tr(ε)/3 · 1, the deviatoric (volume-preserving) part of a principal strain.
template <class T>
ROMP_HD_INLINE Vec3<T> deviatoric(const Vec3<T>& principal) {
  return principal - Vec3<T>::constant(trace(principal) / T(3));
}

template <class T>
struct HenckyStVK {
  T mu;
  T lambda;

  static constexpr bool kPlastic = false;

  ROMP_HD T energy_density(const Mat3<T>& F) const { return isotropic_energy_density(*this, F); }
  ROMP_HD Mat3<T> first_piola(const Mat3<T>& F) const { return isotropic_first_piola(*this, F); }
  ROMP_HD Mat3<T> first_piola_differential(const Mat3<T>& F, const Mat3<T>& dF) const {
    return isotropic_first_piola_differential(*this, F, dF);
  }

  ROMP_HD T principal_energy(const Vec3<T>& sigma) const {
    const Vec3<T> strain = hencky_strain(sigma);
    const T volumetric = trace(strain);
    return mu * squared_norm(strain) + T(0.5) * lambda * volumetric * volumetric;
  }

  // The principal Kirchhoff stress τ̂ = 2μ ε + λ tr(ε) 1.
  ROMP_HD Vec3<T> principal_kirchhoff(const Vec3<T>& strain) const {
    return T(2) * mu * strain + Vec3<T>::constant(lambda * trace(strain));
  }

  // P̂ᵢ = τ̂ᵢ / σᵢ (P = τ F⁻ᵀ), at the clamped stretch.
  ROMP_HD Vec3<T> principal_stress(const Vec3<T>& sigma) const {
    const Vec3<T> stretch = clamped_stretch(sigma);
    const Vec3<T> kirchhoff = principal_kirchhoff(hencky_strain(sigma));
    return Vec3<T>(kirchhoff[0] / stretch[0], kirchhoff[1] / stretch[1], kirchhoff[2] / stretch[2]);
  }

  // Dᵢⱼ = ((2μ δᵢⱼ + λ)/(σᵢσⱼ) − δᵢⱼ P̂ᵢ/σᵢ) for unclamped σⱼ; a clamped σⱼ does not move P̂ (column 0).
  ROMP_HD Mat3<T> principal_stress_derivative(const Vec3<T>& sigma) const {
    const Vec3<T> stretch = clamped_stretch(sigma);
    const Vec3<T> stress = principal_stress(sigma);
    const Vec3<T> inverse(T(1) / stretch[0], T(1) / stretch[1], T(1) / stretch[2]);
    Mat3<T> D = lambda * Mat3<T>::outer(inverse, inverse);
    for (int i = 0; i < 3; ++i) D(i, i) += (T(2) * mu * inverse[i] - stress[i]) * inverse[i];
    for (int j = 0; j < 3; ++j) {
      const bool clamped = !(sigma[j] > kMinHenckyStretch<T>);
      for (int i = 0; i < 3; ++i) D(i, j) = math::select(clamped, T(0), D(i, j));
    }
    return D;
  }
};

}  // namespace romp::material
