// Volume-ratio helpers of the models written in J = det F: the cofactor ∂J/∂F, its differential, and the J clamp.
#pragma once

#include "kernels/core/hd.h"
#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"

namespace romp::material {

// Smallest volume ratio the J-based models take log J or J^(1/3) of. J ≤ 0 (an inverted or
// collapsed element) has neither; below this value the models continue as documented on each
// (NeoHookean: energy linear in J; WeaklyCompressibleFluid: reset to this volume). 1e-6 is a
// compression to a millionth of the rest volume, far beyond physical states, and log(1e-6) ≈ −13.8
// with 1/J = 1e6 keeps the stresses finite in float.
template <class T>
inline constexpr T kMinVolumeRatio = T(1e-6);

// cof F = ∂J/∂F = J F⁻ᵀ, by columns: for F = [a b c], cof F = [b × c, c × a, a × b]. A polynomial
// in F, so it stays finite (and correct) for singular and inverted F where F⁻ᵀ does not exist.
template <class T>
ROMP_HD_INLINE Mat3<T> cofactor(const Mat3<T>& F) {
  const Vec3<T> a = F.column(0), b = F.column(1), c = F.column(2);
  return Mat3<T>::from_columns(cross(b, c), cross(c, a), cross(a, b));
}

// δ(cof F) along δF: the product rule on each column's cross product.
template <class T>
ROMP_HD_INLINE Mat3<T> cofactor_differential(const Mat3<T>& F, const Mat3<T>& dF) {
  const Vec3<T> a = F.column(0), b = F.column(1), c = F.column(2);
  const Vec3<T> da = dF.column(0), db = dF.column(1), dc = dF.column(2);
  return Mat3<T>::from_columns(cross(db, c) + cross(b, dc), cross(dc, a) + cross(c, da), cross(da, b) + cross(a, db));
}

// J = σ₀σ₁σ₂ as a function of the (signed) singular values: ∂J/∂σ, the products of the other two,
// with no division, so it holds for flat and inverted F alike.
template <class T>
ROMP_HD_INLINE Vec3<T> principal_volume_gradient(const Vec3<T>& sigma) {
  return Vec3<T>(sigma[1] * sigma[2], sigma[0] * sigma[2], sigma[0] * sigma[1]);
}

// ∂²J/∂σᵢ∂σⱼ = σₖ for i ≠ j (k the third index), 0 on the diagonal.
template <class T>
ROMP_HD_INLINE Mat3<T> principal_volume_hessian(const Vec3<T>& sigma) {
  return Mat3<T>(T(0), sigma[2], sigma[1], sigma[2], T(0), sigma[0], sigma[1], sigma[0], T(0));
}

}  // namespace romp::material
