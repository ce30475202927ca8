// Backward passes of svd3 and polar3: dL/dF from the gradients of the outputs, with a documented
// regularisation that keeps them finite for repeated singular values.
//
// Derivation (Papadopoulo & Lourakis 2000, "Estimating the Jacobian of the Singular Value
// Decomposition"; Townsend 2016, "Differentiating the Singular Value Decomposition"). Write
// F = U Σ Vᵀ and dP = Uᵀ dF V. Because U and V stay orthogonal, Ω_U = Uᵀ dU and Ω_V = Vᵀ dV are
// skew, and differentiating Σ = Uᵀ F V gives dP = Ω_U Σ + dΣ - Σ Ω_V. Its diagonal is dσᵢ = dPᵢᵢ;
// for i ≠ j the pair (dPᵢⱼ, dPⱼᵢ) solves to
//   Ω_U,ij = (σⱼ dPᵢⱼ + σᵢ dPⱼᵢ) / (σⱼ² - σᵢ²),   Ω_V,ij = (σᵢ dPᵢⱼ + σⱼ dPⱼᵢ) / (σⱼ² - σᵢ²).
// Nothing here assumes σ ≥ 0, so the same formulas hold with romp's sign convention (σ₂ < 0 for
// inverted F). Contracting with the incoming gradients, dL = ⟨Ū, U Ω_U⟩ + ⟨Σ̄, dσ⟩ + ⟨V̄, V Ω_V⟩, and
// with a = (UᵀŪ)ᵢⱼ - (UᵀŪ)ⱼᵢ, b = (VᵀV̄)ᵢⱼ - (VᵀV̄)ⱼᵢ for i < j, the gradient with respect to P is
//   P̄ᵢᵢ = Σ̄ᵢ,
//   P̄ᵢⱼ = -(a + b) / (2 (σᵢ - σⱼ)) + (a - b) / (2 (σᵢ + σⱼ)),
//   P̄ⱼᵢ = -(a + b) / (2 (σᵢ - σⱼ)) - (a - b) / (2 (σᵢ + σⱼ)),
// (splitting 1/(σⱼ² - σᵢ²) into its two factors), and dL/dF = U P̄ Vᵀ.
//
// For polar R = U Vᵀ: Uᵀ dR V = Ω_U - Ω_V, whose (i, j) entry is (dPᵢⱼ - dPⱼᵢ) / (σᵢ + σⱼ); with
// M = Uᵀ R̄ V, P̄ᵢⱼ = -P̄ⱼᵢ = (Mᵢⱼ - Mⱼᵢ) / (σᵢ + σⱼ). Only σᵢ + σⱼ appears: the rotation is smooth
// through repeated singular values and singular only where two of them cancel (rank ≤ 1, or an
// inverted F with σ₂ = -σ₁). For S = Rᵀ F, dS = dRᵀ F + Rᵀ dF, so R̄ gains F S̄ᵀ and dL/dF gains R S̄.
//
// Regularisation. With σ₀ ≥ σ₁ ≥ |σ₂| both σᵢ - σⱼ and σᵢ + σⱼ (i < j) are non-negative. Each is
// clamped from below by g = max(kGradientGapFloor |σ₀|, kNegligible) (Svd3Config) before taking the
// reciprocal, keeping its sign (sign(0) = +1). The clamp leaves every gradient with gaps above g
// exact, is continuous, and bounds the rotational part of the gradient by 1/g; for exactly
// repeated singular values the rotation of the singular vectors within their subspace is arbitrary
// and losses that do not depend on it (functions of F, such as the polar rotation) give a + b = 0 there.
#pragma once

#include "kernels/core/hd.h"
#include "kernels/math/mat3.h"
#include "kernels/math/scalar.h"
#include "kernels/math/vec3.h"
#include "kernels/svd/svd3.h"

namespace romp {
namespace svd_detail {

// The clamp floor g of the regularisation, from the largest singular value.
template <class T>
ROMP_MATH_INLINE T gradient_gap_floor(const Vec3<T>& sigma) {
  return math::max(Svd3Config<T>::kGradientGapFloor * math::abs(sigma[0]), Svd3Config<T>::kNegligible);
}

// 1 / x with |x| clamped from below by `floor`, sign kept.
template <class T>
ROMP_MATH_INLINE T clamped_reciprocal(T x, T floor) {
  return T(1) / (math::sign(x) * math::max(math::abs(x), floor));
}

// Fills P̄ᵢⱼ and P̄ⱼᵢ for one pair i < j of the SVD backward pass.
template <int i, int j, class T>
ROMP_MATH_INLINE void svd_pair_gradient(const Mat3<T>& Ut_dU, const Mat3<T>& Vt_dV, const Vec3<T>& sigma, T floor,
                                        Mat3<T>& P) {
  const T a = Ut_dU.m[i][j] - Ut_dU.m[j][i];
  const T b = Vt_dV.m[i][j] - Vt_dV.m[j][i];
  const T symmetric = -T(0.5) * (a + b) * clamped_reciprocal(sigma[i] - sigma[j], floor);
  const T antisymmetric = T(0.5) * (a - b) * clamped_reciprocal(sigma[i] + sigma[j], floor);
  P.m[i][j] = symmetric + antisymmetric;
  P.m[j][i] = symmetric - antisymmetric;
}

// Fills P̄ᵢⱼ = -P̄ⱼᵢ for one pair i < j of the polar rotation's backward pass.
template <int i, int j, class T>
ROMP_MATH_INLINE void polar_pair_gradient(const Mat3<T>& M, const Vec3<T>& sigma, T floor, Mat3<T>& P) {
  const T value = (M.m[i][j] - M.m[j][i]) * clamped_reciprocal(sigma[i] + sigma[j], floor);
  P.m[i][j] = value;
  P.m[j][i] = -value;
}

}  // namespace svd_detail

// dL/dF from dL/dU, dL/dσ and dL/dV at F = U diag(σ) Vᵀ (the result of svd3(F)).
template <class T>
ROMP_MATH_INLINE Mat3<T> svd3_backward(const Svd3<T>& svd, const Mat3<T>& dU, const Vec3<T>& dsigma,
                                       const Mat3<T>& dV) {
  using namespace svd_detail;
  const T floor = gradient_gap_floor(svd.sigma);
  const Mat3<T> Ut_dU = transpose_times(svd.U, dU);
  const Mat3<T> Vt_dV = transpose_times(svd.V, dV);
  Mat3<T> P = Mat3<T>::diag(dsigma);
  svd_pair_gradient<0, 1>(Ut_dU, Vt_dV, svd.sigma, floor, P);
  svd_pair_gradient<0, 2>(Ut_dU, Vt_dV, svd.sigma, floor, P);
  svd_pair_gradient<1, 2>(Ut_dU, Vt_dV, svd.sigma, floor, P);
  return times_transpose(svd.U * P, svd.V);
}

// dL/dF from dL/dR and dL/dS of the polar decomposition F = R S, given svd = svd3(F).
template <class T>
ROMP_MATH_INLINE Mat3<T> polar3_backward(const Svd3<T>& svd, const Mat3<T>& dR, const Mat3<T>& dS) {
  using namespace svd_detail;
  const T floor = gradient_gap_floor(svd.sigma);
  const Mat3<T> R = times_transpose(svd.U, svd.V);
  const Mat3<T> F = times_transpose(svd.U * Mat3<T>::diag(svd.sigma), svd.V);
  // S = Rᵀ F: R̄ gains F S̄ᵀ, and F̄ gains R S̄ directly.
  const Mat3<T> M = transpose_times(svd.U, dR + times_transpose(F, dS)) * svd.V;
  Mat3<T> P = Mat3<T>::zero();
  polar_pair_gradient<0, 1>(M, svd.sigma, floor, P);
  polar_pair_gradient<0, 2>(M, svd.sigma, floor, P);
  polar_pair_gradient<1, 2>(M, svd.sigma, floor, P);
  return times_transpose(svd.U * P, svd.V) + R * dS;
}

}  // namespace romp
