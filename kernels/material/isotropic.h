// Isotropic hyperelasticity through the signed SVD: ψ, P = U diag(P̂) Vᵀ and δP from principal-space functions.
//
// An isotropic energy depends on F only through its singular values, ψ(F) = ψ̂(σ). romp uses the
// signed SVD of svd3 (σ₀ ≥ σ₁ ≥ |σ₂|, σ₂ < 0 exactly when det F < 0), so inverted elements keep the
// sign of their volume in σ₂ (Irving, Teran, Fedkiw 2004, "Invertible finite elements"). A model
// provides, as functions of σ,
//   principal_energy(σ)              ψ̂(σ),
//   principal_stress(σ)              P̂ᵢ, which is ∂ψ̂/∂σᵢ wherever the model needs no clamp,
//   principal_stress_derivative(σ)   Dᵢⱼ = ∂P̂ᵢ/∂σⱼ,
// and forwards its energy_density / first_piola / first_piola_differential to the functions below.
// NeoHookean and the fluid, whose own P and δP need no SVD, provide the stress and its derivative
// as well: the semidefinite stiffness of the implicit step (PrincipalStiffness::definite) lives in
// this frame, so every model reaches it through isotropic_stiffness.
//
// Differential (Teran, Sifakis, Irving, Fedkiw 2005, "Robust quasistatic finite elements and flesh
// simulation"; Sifakis & Barbič 2012, "FEM simulation of 3D deformable solids", SIGGRAPH course). In the rotated frame
// dF̂ = Uᵀ δF V, the same frame as P̂: dP̂ = Ω_U P̂ + δP̂ − P̂ Ω_V and dF̂ = Ω_U Σ + δΣ − Σ Ω_V with
// Ω_U = Uᵀ δU, Ω_V = Vᵀ δV skew. The diagonal gives dP̂ᵢᵢ = Σⱼ Dᵢⱼ dF̂ⱼⱼ. For each pair i < j the
// off-diagonal entries decouple into a symmetric and a skew part,
//   dP̂ᵢⱼ + dP̂ⱼᵢ = (P̂ᵢ − P̂ⱼ)/(σᵢ − σⱼ) (dF̂ᵢⱼ + dF̂ⱼᵢ),
//   dP̂ᵢⱼ − dP̂ⱼᵢ = (P̂ᵢ + P̂ⱼ)/(σᵢ + σⱼ) (dF̂ᵢⱼ − dF̂ⱼᵢ),
// and δP = U dP̂ Vᵀ. Nothing assumes σ > 0, so the same formula holds for inverted F.
//
// Repeated singular values. Where |σᵢ − σⱼ| (or |σᵢ + σⱼ|) falls below the gap floor g, the
// quotient is replaced by its limit: for ψ̂ symmetric in its arguments, (P̂ᵢ − P̂ⱼ)/(σᵢ − σⱼ) →
// ½(Dᵢᵢ + Dⱼⱼ) − ½(Dᵢⱼ + Dⱼᵢ) as σⱼ → σᵢ, and for ψ̂ also even under flipping the signs of a pair,
// (P̂ᵢ + P̂ⱼ)/(σᵢ + σⱼ) → ½(Dᵢᵢ + Dⱼⱼ) + ½(Dᵢⱼ + Dⱼᵢ) as σⱼ → −σᵢ. The first limit is exact for every
// isotropic model (so δP stays accurate at F = I); the second is exact for sign-even models and,
// for the others (fixed corotated, Hencky), is a bounded stand-in at a point where their P is not
// differentiable (an inverted F with σ₂ = −σ₁, a set of measure zero). g = max(ε_g |σ₀|, ν) with
// ε_g = Svd3Config::kGradientGapFloor (√ε of the precision: closer singular values are not
// resolved by the SVD itself, and the quotient's rounding error ε/gap equals the limit's
// truncation error gap there) and ν = Svd3Config::kNegligible (for F ≈ 0).
#pragma once

#include "kernels/core/hd.h"
#include "kernels/math/mat3.h"
#include "kernels/math/scalar.h"
#include "kernels/math/vec3.h"
#include "kernels/svd/svd3.h"
#include "kernels/svd/symmetric_eigen3.h"

namespace romp::material {

// U diag(d) Vᵀ: a principal-space diagonal back in the frame of F.
template <class T>
ROMP_HD_INLINE Mat3<T> from_principal(const Mat3<T>& U, const Vec3<T>& d, const Mat3<T>& V) {
  Mat3<T> U_d = U;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) U_d(r, c) *= d[c];
  return times_transpose(U_d, V);
}

namespace isotropic_detail {

// numerator / denominator, or `limit` when |denominator| ≤ gap_floor (see the header comment).
template <class T>
ROMP_HD_INLINE T quotient_or_limit(T numerator, T denominator, T limit, T gap_floor) {
  const bool resolved = math::abs(denominator) > gap_floor;
  return math::select(resolved, numerator / math::select(resolved, denominator, T(1)), limit);
}

// The rotational pairs (i, j), i < j, in the order PrincipalStiffness stores their moduli.
ROMP_HD_INLINE int pair_first(int pair) { return pair < 2 ? 0 : 1; }
ROMP_HD_INLINE int pair_second(int pair) { return pair == 0 ? 1 : 2; }

}  // namespace isotropic_detail

// ∂P/∂F at one F, in the principal frame of the signed SVD F = U Σ Vᵀ (see the header comment):
// the 3x3 block D on the diagonal of dF̂ = Uᵀ δF V, and for each pair i < j the moduli of its
// symmetric and skew parts. Built once per F, it applies to any number of δF at the cost of two
// frame changes, which is what an iterative solver that applies the same stiffness many times needs.
template <class T>
struct PrincipalStiffness {
  Mat3<T> U, V;
  Mat3<T> D;                  // Dᵢⱼ = ∂P̂ᵢ/∂σⱼ
  Vec3<T> symmetric_modulus;  // pairs (0, 1), (0, 2), (1, 2): (P̂ᵢ − P̂ⱼ)/(σᵢ − σⱼ) or its limit
  Vec3<T> skew_modulus;       // the same pairs: (P̂ᵢ + P̂ⱼ)/(σᵢ + σⱼ) or its limit

  // δP = ∂P/∂F : δF.
  ROMP_HD Mat3<T> apply(const Mat3<T>& dF) const {
    const Mat3<T> dF_hat = transpose_times(U, dF * V);
    Mat3<T> dP_hat = Mat3<T>::diag(D * diagonal(dF_hat));
    for (int pair = 0; pair < 3; ++pair) {
      const int i = isotropic_detail::pair_first(pair), j = isotropic_detail::pair_second(pair);
      const T symmetric_part = T(0.5) * (dF_hat(i, j) + dF_hat(j, i));
      const T skew_part = T(0.5) * (dF_hat(i, j) - dF_hat(j, i));
      dP_hat(i, j) = symmetric_modulus[pair] * symmetric_part + skew_modulus[pair] * skew_part;
      dP_hat(j, i) = symmetric_modulus[pair] * symmetric_part - skew_modulus[pair] * skew_part;
    }
    return U * times_transpose(dP_hat, V);
  }

  // The definiteness fix of Teran, Sifakis, Irving, Fedkiw 2005 (Sec. 5; Eq. 16 of the enriched-MPM
  // paper): the nearest positive semidefinite stiffness of the same block structure. In the
  // principal frame δF : δP = Σᵢⱼ dF̂ᵢᵢ Dᵢⱼ dF̂ⱼⱼ + Σ_pairs 2 (a sym² + b skew²), so the stiffness
  // is semidefinite exactly when D is and every modulus a, b is ≥ 0; negative eigenvalues of D and
  // negative moduli are set to zero. D is symmetrised first: only its symmetric part enters the
  // quadratic form, and a solver needs a symmetric operator (HenckyStVK's D is not symmetric where
  // it clamps a stretch). Where the stiffness already is semidefinite (and D symmetric) nothing changes.
  ROMP_HD PrincipalStiffness definite() const {
    const Mat3<T> D_symmetric = T(0.5) * (D + transpose(D));
    PrincipalStiffness projected = *this;
    projected.D = positive_semidefinite_part(D_symmetric);
    for (int pair = 0; pair < 3; ++pair) {
      projected.symmetric_modulus[pair] = math::max(symmetric_modulus[pair], T(0));
      projected.skew_modulus[pair] = math::max(skew_modulus[pair], T(0));
    }
    return projected;
  }
};

template <class Model, class T>
ROMP_HD T isotropic_energy_density(const Model& model, const Mat3<T>& F) {
  return model.principal_energy(svd3(F).sigma);
}

template <class Model, class T>
ROMP_HD Mat3<T> isotropic_first_piola(const Model& model, const Mat3<T>& F) {
  const Svd3<T> svd = svd3(F);
  return from_principal(svd.U, model.principal_stress(svd.sigma), svd.V);
}

template <class Model, class T>
ROMP_HD PrincipalStiffness<T> isotropic_stiffness(const Model& model, const Mat3<T>& F) {
  const Svd3<T> svd = svd3(F);
  const Vec3<T>& sigma = svd.sigma;
  const Vec3<T> stress = model.principal_stress(sigma);
  PrincipalStiffness<T> stiffness{svd.U, svd.V, model.principal_stress_derivative(sigma), Vec3<T>::zero(),
                                  Vec3<T>::zero()};
  const Mat3<T>& D = stiffness.D;
  const T gap_floor = math::max(Svd3Config<T>::kGradientGapFloor * math::abs(sigma[0]), Svd3Config<T>::kNegligible);
  for (int pair = 0; pair < 3; ++pair) {
    const int i = isotropic_detail::pair_first(pair), j = isotropic_detail::pair_second(pair);
    const T diagonal_mean = T(0.5) * (D(i, i) + D(j, j));
    const T cross_mean = T(0.5) * (D(i, j) + D(j, i));
    stiffness.symmetric_modulus[pair] = isotropic_detail::quotient_or_limit(stress[i] - stress[j], sigma[i] - sigma[j],
                                                                            diagonal_mean - cross_mean, gap_floor);
    stiffness.skew_modulus[pair] = isotropic_detail::quotient_or_limit(stress[i] + stress[j], sigma[i] + sigma[j],
                                                                       diagonal_mean + cross_mean, gap_floor);
  }
  return stiffness;
}

template <class Model, class T>
ROMP_HD Mat3<T> isotropic_first_piola_differential(const Model& model, const Mat3<T>& F, const Mat3<T>& dF) {
  return isotropic_stiffness(model, F).apply(dF);
}

}  // namespace romp::material
