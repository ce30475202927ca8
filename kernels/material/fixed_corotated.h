// Fixed corotated elasticity (Stomakhin et al. 2012): ψ = μ‖F − R‖²_F + λ/2 (J − 1)².
//
// Stomakhin, Howes, Schroeder, Teran 2012, "Energetically consistent invertible elasticity"; the
// jelly ground truth of Ma et al. 2023 (App. B, Eq. 12). With R = U Vᵀ the polar rotation of the
// signed SVD, ‖F − R‖²_F = Σᵢ (σᵢ − 1)² and J = σ₀σ₁σ₂, so ψ̂(σ) = μ Σᵢ (σᵢ − 1)² + λ/2 (J − 1)² and
//   P = 2μ (F − R) + λ (J − 1) J F⁻ᵀ = U diag(P̂) Vᵀ,  P̂ᵢ = 2μ (σᵢ − 1) + λ (J − 1) ∂J/∂σᵢ,
// with ∂J/∂σᵢ = σⱼσₖ (j, k the other two indices): a polynomial, finite for every finite F,
// including inverted (σ₂ < 0) and degenerate ones.
#pragma once

#include "kernels/core/hd.h"
#include "kernels/material/isotropic.h"
#include "kernels/material/volume.h"
#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"

namespace romp::material {

template <class T>
struct FixedCorotated {
  T mu;
  T lambda;

  static constexpr bool kPlastic = false;

  ROMP_HD T energy_density(const Mat3<T>& F) const { return isotropic_energy_density(*this, F); }
  ROMP_HD Mat3<T> first_piola(const Mat3<T>& F) const { return isotropic_first_piola(*this, F); }
  ROMP_HD Mat3<T> first_piola_differential(const Mat3<T>& F, const Mat3<T>& dF) const {
    return isotropic_first_piola_differential(*this, F, dF);
  }

  ROMP_HD T principal_energy(const Vec3<T>& sigma) const {
    const Vec3<T> stretch = sigma - Vec3<T>::constant(T(1));
    const T volume_change = sigma[0] * sigma[1] * sigma[2] - T(1);
    return mu * squared_norm(stretch) + T(0.5) * lambda * volume_change * volume_change;
  }

  ROMP_HD Vec3<T> principal_stress(const Vec3<T>& sigma) const {
    const T volume_change = sigma[0] * sigma[1] * sigma[2] - T(1);
    return T(2) * mu * (sigma - Vec3<T>::constant(T(1))) + lambda * volume_change * principal_volume_gradient(sigma);
  }

  // D = 2μ I + λ (∂J/∂σ)(∂J/∂σ)ᵀ + λ (J − 1) ∂²J/∂σ².
  ROMP_HD Mat3<T> principal_stress_derivative(const Vec3<T>& sigma) const {
    const Vec3<T> gradient = principal_volume_gradient(sigma);
    const T volume_change = sigma[0] * sigma[1] * sigma[2] - T(1);
    return T(2) * mu * Mat3<T>::identity() + lambda * Mat3<T>::outer(gradient, gradient) +
           lambda * volume_change * principal_volume_hessian(sigma);
  }
};

}  // namespace romp::material
