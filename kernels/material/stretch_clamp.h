// Inversion handling for hyperelastic stress: principal stretches below a floor are raised to it.
//
// Irving, Teran, Fedkiw 2004 ("Invertible finite elements"), as the enriched MPM of Zhu et al.
// (Sec. 5.3) uses it: with the signed SVD F = U Σ Vᵀ (σ₂ < 0 exactly when F is inverted), the stress
// is evaluated at F̃ = U diag(max(σᵢ, floor)) Vᵀ. For an isotropic model P(F̃) = U P̂(σ̃) Vᵀ, so this is
// the paper's "clamp the entries of F̂, then P = U P̂ Vᵀ": a flat or inverted element gets the stress
// of a merely compressed one, finite and pushing it back to positive volume. The energy and the
// stress differential are evaluated at F̃ too; in clamped directions they are therefore the model's
// values at the floor, not derivatives of the clamped map (the implicit solve wants exactly that:
// the stiffness of a valid state).
#pragma once

#include "kernels/core/hd.h"
#include "kernels/material/isotropic.h"
#include "kernels/math/mat3.h"
#include "kernels/math/scalar.h"
#include "kernels/svd/svd3.h"

namespace romp::material {

// Whether every principal stretch of F is at least `floor`, decided without an SVD where it can be:
// σ_min = J / (σ_a σ_b) and σ_a σ_b ≤ (σ_a² + σ_b²) / 2 ≤ ‖F‖²/2, so σ_min ≥ 2J / ‖F‖². True means
// certainly; false means "take the SVD" (it also holds for J ≤ 0 whenever floor ≥ 0).
template <class T>
ROMP_HD_INLINE bool stretches_surely_at_least(const Mat3<T>& F, T floor) {
  return T(2) * determinant(F) > floor * squared_frobenius_norm(F);
}

// F with every principal stretch at least `floor`; F itself (bit for bit) when none is below, or
// when floor ≤ 0 (clamping off).
template <class T>
ROMP_HD Mat3<T> clamp_stretches(const Mat3<T>& F, T floor) {
  if (!(floor > T(0))) return F;
  // Passes for every moderately deformed F (F = I: 2/3 against a floor of 0.1).
  if (stretches_surely_at_least(F, floor)) return F;
  const Svd3<T> svd = svd3(F);
  // σ₂ is the smallest signed singular value (svd3 sorts them).
  if (svd.sigma[2] >= floor) return F;
  Vec3<T> sigma = svd.sigma;
  for (int i = 0; i < 3; ++i) sigma[i] = math::max(sigma[i], floor);
  return from_principal(svd.U, sigma, svd.V);
}

}  // namespace romp::material
