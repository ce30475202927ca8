// Compressible neo-Hookean elasticity: ψ = μ/2 (tr FᵀF − 3) − μ log J + λ/2 (log J)².
//
// The compressible form of Bonet & Wood, "Nonlinear continuum mechanics for finite element
// analysis", as used for MPM by Jiang et al. 2016, "The material point method for simulating
// continuum materials" (SIGGRAPH course):
//   P = μ (F − F⁻ᵀ) + λ log J F⁻ᵀ = μ F + φ'(J) cof F,   φ(J) = −μ log J + λ/2 (log J)²,
// written with cof F = J F⁻ᵀ (volume.h) so no inverse is formed, and
//   δP = μ δF + φ''(J) (cof F : δF) cof F + φ'(J) δ(cof F).
// No SVD is needed. J ≤ 0: log J does not exist, so below kMinVolumeRatio the volumetric energy φ
// is continued by its tangent line, φ(J) = φ(J₀) + φ'(J₀)(J − J₀) with J₀ = kMinVolumeRatio. The
// energy stays C¹ and finite for every finite F, P is still exactly ∂ψ/∂F and pushes J back up
// with the (large, bounded) pressure φ'(J₀), and φ'' = 0 there.
#pragma once

#include <cmath>

#include "kernels/core/hd.h"
#include "kernels/material/volume.h"
#include "kernels/math/mat3.h"
#include "kernels/math/scalar.h"
#include "kernels/math/vec3.h"

namespace romp::material {

template <class T>
struct NeoHookean {
  T mu;
  T lambda;

  static constexpr bool kPlastic = false;

  ROMP_HD T energy_density(const Mat3<T>& F) const {
    const T J = determinant(F);
    const T J_used = math::max(J, kMinVolumeRatio<T>);
    const T log_J = std::log(J_used);
    // The tangent-line term vanishes for J ≥ kMinVolumeRatio (J_used = J).
    const T volumetric = -mu * log_J + T(0.5) * lambda * log_J * log_J + volume_slope(J_used, log_J) * (J - J_used);
    return T(0.5) * mu * (squared_frobenius_norm(F) - T(3)) + volumetric;
  }

  ROMP_HD Mat3<T> first_piola(const Mat3<T>& F) const {
    const T J_used = math::max(determinant(F), kMinVolumeRatio<T>);
    return mu * F + volume_slope(J_used, std::log(J_used)) * cofactor(F);
  }

  ROMP_HD Mat3<T> first_piola_differential(const Mat3<T>& F, const Mat3<T>& dF) const {
    const T J = determinant(F);
    const T J_used = math::max(J, kMinVolumeRatio<T>);
    const T log_J = std::log(J_used);
    const Mat3<T> cof = cofactor(F);
    return mu * dF + (volume_curvature(J, J_used, log_J) * inner(cof, dF)) * cof +
           volume_slope(J_used, log_J) * cofactor_differential(F, dF);
  }

  // The same P in the principal frame of the signed SVD (isotropic.h), where the implicit step's
  // semidefinite stiffness is formed: with J = σ₀σ₁σ₂ and cof F = U diag(∂J/∂σ) Vᵀ,
  //   P̂ = μ σ + φ'(J) ∂J/∂σ,   D = μ I + φ''(J) (∂J/∂σ)(∂J/∂σ)ᵀ + φ'(J) ∂²J/∂σ².
  ROMP_HD Vec3<T> principal_stress(const Vec3<T>& sigma) const {
    const T J_used = math::max(sigma[0] * sigma[1] * sigma[2], kMinVolumeRatio<T>);
    return mu * sigma + volume_slope(J_used, std::log(J_used)) * principal_volume_gradient(sigma);
  }

  ROMP_HD Mat3<T> principal_stress_derivative(const Vec3<T>& sigma) const {
    const T J = sigma[0] * sigma[1] * sigma[2];
    const T J_used = math::max(J, kMinVolumeRatio<T>);
    const T log_J = std::log(J_used);
    const Vec3<T> gradient = principal_volume_gradient(sigma);
    return mu * Mat3<T>::identity() + volume_curvature(J, J_used, log_J) * Mat3<T>::outer(gradient, gradient) +
           volume_slope(J_used, log_J) * principal_volume_hessian(sigma);
  }

 private:
  // φ'(J) = (λ log J − μ) / J.
  ROMP_HD T volume_slope(T J, T log_J) const { return (lambda * log_J - mu) / J; }
  // φ''(J) = (λ (1 − log J) + μ) / J², zero on the tangent-line continuation.
  ROMP_HD T volume_curvature(T J, T J_used, T log_J) const {
    return math::select(J > kMinVolumeRatio<T>, (lambda * (T(1) - log_J) + mu) / (J_used * J_used), T(0));
  }
};

}  // namespace romp::material
