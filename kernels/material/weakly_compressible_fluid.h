// Weakly compressible fluid: Kirchhoff stress τ = λ J (J − 1) I, and F reset to its volume part after each step.
//
// Ma et al. 2023, "Learning neural constitutive laws from motion observations", App. B, Eqs. (20)-(21),
// following Stomakhin et al. 2014 and Tampubolon et al. 2017: fixed corotated elasticity with μ = 0,
//   ψ = λ/2 (J − 1)²,  P = λ (J − 1) J F⁻ᵀ = λ (J − 1) cof F,  δP = λ (cof F : δF) cof F + λ (J − 1) δ(cof F),
// so τ = P Fᵀ = λ J (J − 1) I (no shear resistance, a pressure penalising volume change). Written
// with the cofactor (volume.h), P is a polynomial in F: finite for every finite F, inverted included.
// The "plasticity" forgets every shear: F ← J^(1/3) I (the paper's Eq. 21), keeping J.
#pragma once

#include <cmath>

#include "kernels/core/hd.h"
#include "kernels/material/fixed_corotated.h"
#include "kernels/material/plastic_return.h"
#include "kernels/material/volume.h"
#include "kernels/math/mat3.h"
#include "kernels/math/scalar.h"

namespace romp::material {

template <class T>
struct WeaklyCompressibleFluid {
  T lambda;  // bulk stiffness λ (Pa): the first Lamé parameter of the paper's (E, ν)

  static constexpr bool kPlastic = true;

  ROMP_HD T energy_density(const Mat3<T>& F) const {
    const T volume_change = determinant(F) - T(1);
    return T(0.5) * lambda * volume_change * volume_change;
  }

  ROMP_HD Mat3<T> first_piola(const Mat3<T>& F) const { return lambda * (determinant(F) - T(1)) * cofactor(F); }

  ROMP_HD Mat3<T> first_piola_differential(const Mat3<T>& F, const Mat3<T>& dF) const {
    const Mat3<T> cof = cofactor(F);
    return (lambda * inner(cof, dF)) * cof + lambda * (determinant(F) - T(1)) * cofactor_differential(F, dF);
  }

  // In the principal frame (isotropic.h), for the implicit step's semidefinite stiffness: the
  // principal stress and its derivative of fixed corotated with μ = 0, which this model is.
  ROMP_HD Vec3<T> principal_stress(const Vec3<T>& sigma) const {
    return FixedCorotated<T>{T(0), lambda}.principal_stress(sigma);
  }
  ROMP_HD Mat3<T> principal_stress_derivative(const Vec3<T>& sigma) const {
    return FixedCorotated<T>{T(0), lambda}.principal_stress_derivative(sigma);
  }

  // J^(1/3) I with the same J, for J ≥ kMinVolumeRatio (tiny positive J included down to it; cbrt
  // is exact in sign and has no domain error). J < kMinVolumeRatio, which only a failed step
  // produces (J ≤ 0 means the particle was compressed through zero volume), is reset to
  // kMinVolumeRatio^(1/3) I: an uninverted, maximally compressed state whose pressure ≈ λ pushes it
  // open, instead of keeping an unphysical negative volume.
  ROMP_HD Mat3<T> project(const Mat3<T>& F_trial) const {
    const T J = math::max(determinant(F_trial), kMinVolumeRatio<T>);
    const T stretch = std::cbrt(J);
    return Mat3<T>::diag(stretch, stretch, stretch);
  }
  // A fluid keeps no plastic state: resetting its shear is not plastic flow of a solid.
  ROMP_HD PlasticReturn<T> plastic_return(const Mat3<T>& F_trial) const { return {project(F_trial), T(0)}; }
};

}  // namespace romp::material
