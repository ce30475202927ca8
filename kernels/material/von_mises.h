// Von Mises elastoplasticity for plasticine: HenckyStVK elasticity and a radial return of the deviatoric Hencky strain.
//
// The yield condition bounds the deviatoric Kirchhoff stress, ‖dev τ‖ = 2μ ‖ε̂‖ ≤ τ_y, with ε = log Σ
// the Hencky strain and ε̂ its deviatoric part (the plasticine ground truth of Ma et al. 2023,
// "Learning neural constitutive laws from motion observations", App. B, Eqs. 18-19). Plastic flow is isochoric,
// so the return map keeps tr ε and scales ε̂ back to the yield radius τ_y/(2μ):
//   ε ← ε − (‖ε̂‖ − τ_y/(2μ)) ε̂/‖ε̂‖  when ‖ε̂‖ > τ_y/(2μ),  F = U exp(ε) Vᵀ.
// (Some authors bound ‖dev τ‖ by √(2/3) τ_y instead; romp follows the paper's convention.)
#pragma once

#include "kernels/core/hd.h"
#include "kernels/material/hencky.h"
#include "kernels/material/plastic_return.h"
#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"
#include "kernels/svd/svd3.h"

namespace romp::material {

template <class T>
struct VonMises : HenckyStVK<T> {
  T yield_stress;  // τ_y, a Kirchhoff stress (Pa)

  static constexpr bool kPlastic = true;

  // The elastic F on or inside the yield cylinder for a trial F; U, V and tr ε of the trial are kept.
  ROMP_HD PlasticReturn<T> plastic_return(const Mat3<T>& F_trial) const {
    const Svd3<T> svd = svd3(F_trial);
    const Vec3<T> strain = hencky_strain(svd.sigma);
    const Vec3<T> deviator = deviatoric(strain);
    const T deviator_norm = norm(deviator);
    const T yield_radius = yield_stress / (T(2) * this->mu);
    if (!(deviator_norm > yield_radius)) return {F_trial, T(0)};
    const T removed = deviator_norm - yield_radius;  // ‖Δε‖: the strain moves along the deviator
    return {from_hencky_strain(svd, strain - (removed / deviator_norm) * deviator), removed};
  }
  ROMP_HD Mat3<T> project(const Mat3<T>& F_trial) const { return plastic_return(F_trial).F; }
};

}  // namespace romp::material
