// Drucker-Prager sand (Klár et al. 2016): HenckyStVK elasticity and a return map in log-strain space.
//
// Klár, Gast, Pradhana, Fu, Schroeder, Jiang, Teran 2016, "Drucker-Prager elastoplasticity for sand
// animation", in the form of Ma et al. 2023 ("Learning neural constitutive laws from motion
// observations", App. B, Eqs. 15-16), the sand ground truth romp reproduces. The yield condition on
// the Kirchhoff stress, ‖dev τ‖ + α tr τ ≤ 0, reads in the Hencky strain ε = log Σ (τ̂ = 2μ ε + λ tr(ε) 1, d = 3)
//   ‖ε̂‖ + α (3λ + 2μ)/(2μ) tr ε ≤ 0,   α = √(2/3) · 2 sin φ / (3 − sin φ),
// with ε̂ the deviatoric part and φ the friction angle. The return map projects the trial strain:
//   tr ε ≥ 0 (expansion: no confining pressure, no resistance)  →  the cone tip ε = 0 (F = U Vᵀ);
//   δγ = ‖ε̂‖ + α (3λ + 2μ)/(2μ) tr ε ≤ 0 (inside)              →  unchanged;
//   otherwise (shear)                                          →  ε − δγ ε̂/‖ε̂‖, on the cone.
//
// Cohesion convention: `cohesion` c is a log strain that moves the cone tip from ε = 0 to ε = c 1,
// i.e. tr ε is replaced by the shifted trace tr ε − 3c above, and the tip is F = e^c U Vᵀ. c = 0 is
// Klár's cohesionless sand (the neural-constitutive-law paper's ground truth); c > 0 lets the
// material carry a small isotropic tension (up to a stretch of e^c) before it falls apart.
#pragma once

#include <cmath>

#include "kernels/core/hd.h"
#include "kernels/material/hencky.h"
#include "kernels/material/plastic_return.h"
#include "kernels/math/mat3.h"
#include "kernels/math/scalar.h"
#include "kernels/math/vec3.h"
#include "kernels/svd/svd3.h"

namespace romp::material {

template <class T>
inline constexpr T kDegreesToRadians = T(3.14159265358979323846 / 180.0);

// α = √(2/3) · 2 sin φ / (3 − sin φ) for the friction angle φ in degrees (Klár et al. 2016):
// the Drucker-Prager cone inscribed in the Mohr-Coulomb pyramid of that angle. Valid for
// 0 ≤ φ < 90° (α = 0 at φ = 0: no friction, every deviatoric strain is removed).
template <class T>
ROMP_HD T drucker_prager_alpha(T friction_angle_degrees) {
  const T sin_phi = std::sin(friction_angle_degrees * kDegreesToRadians<T>);
  return math::sqrt(T(2) / T(3)) * T(2) * sin_phi / (T(3) - sin_phi);
}

// HenckyStVK elasticity with the return map above; `alpha` from drucker_prager_alpha.
template <class T>
struct DruckerPrager : HenckyStVK<T> {
  T alpha;
  T cohesion;  // log-strain shift of the cone tip (see the file comment); 0 for dry sand

  static constexpr bool kPlastic = true;

  // The elastic F on or inside the yield cone for a trial F; U and V of the trial are kept.
  ROMP_HD PlasticReturn<T> plastic_return(const Mat3<T>& F_trial) const {
    const Svd3<T> svd = svd3(F_trial);
    const Vec3<T> strain = hencky_strain(svd.sigma);
    const T shifted_trace = trace(strain) - T(3) * cohesion;
    if (shifted_trace >= T(0)) {
      // To the cone's tip: the whole strain but the cohesion's shift is removed.
      const Vec3<T> tip = Vec3<T>::constant(cohesion);
      return {from_hencky_strain(svd, tip), norm(strain - tip)};
    }
    const Vec3<T> deviator = deviatoric(strain);
    const T deviator_norm = norm(deviator);
    const T volumetric_stiffness = (T(3) * this->lambda + T(2) * this->mu) / (T(2) * this->mu);
    const T delta_gamma = deviator_norm + alpha * volumetric_stiffness * shifted_trace;
    if (delta_gamma <= T(0)) return {F_trial, T(0)};
    // δγ > 0 and shifted_trace < 0 imply ‖ε̂‖ > 0: the division is safe. ‖Δε‖ = δγ along the deviator.
    return {from_hencky_strain(svd, strain - (delta_gamma / deviator_norm) * deviator), delta_gamma};
  }
  ROMP_HD Mat3<T> project(const Mat3<T>& F_trial) const { return plastic_return(F_trial).F; }
};

}  // namespace romp::material
