// Branch-free 3x3 SVD (F = U Σ Vᵀ) and polar decomposition (F = R S) for single-source kernels.
//
// Method: McAdams, Selle, Tamstorf, Teran, Sifakis 2011, "Computing the Singular Value Decomposition
// of 3x3 matrices with minimal branching and elementary floating point operations" (UW-Madison
// TR1690), referred to below as [McAdams]:
//   1. Jacobi eigenanalysis of the symmetric AᵀA with approximate Givens conjugations, the rotations
//      accumulated as a quaternion, for a fixed number of sweeps (Alg. 2 and §2.1-2.3);
//   2. B = A V, columns sorted by norm with sign-fixing swaps so V stays a rotation (Alg. 3, §2.4);
//   3. QR of B by three Givens rotations: B = U R, with R's diagonal the singular values and the sign
//      of det F left on R's last entry (Alg. 4 and §2.5).
// Two additions make the result meet float/double accuracy on every input class the tests cover:
//   0. A = F 2^-k with 2^k ≤ max|F_ij| < 2^(k+1), an exact scaling, so AᵀA neither overflows nor
//      underflows for any finite F; Σ is scaled back by 2^k at the end.
//   4. The trailing 2x2 block of R is replaced by its exact 2x2 SVD. Forming AᵀA squares the condition
//      number: eigenvectors of AᵀA for singular values below √ε σ₀ come out of step 1 mixed, which
//      leaves an off-diagonal R₁₂ of order √ε σ₀ (3e-4 in float) that [McAdams] discards. R₀₁ and R₀₂
//      are (VᵀAᵀAV)₀ⱼ / R₀₀ with R₀₀ the largest column norm (the pivoting of step 2), of order ε σ₀,
//      so after the 2x2 SVD R is diagonal to working precision.
//   5. Two compare-exchanges on the final values make Σ exactly sorted (σ₀ ≥ σ₁ ≥ |σ₂|) also when
//      repeated singular values differ in the last bit between steps 3 and 4.
// Every decision is a math::select (SEL on the GPU, a bit blend on the CPU), never a branch: a warp
// never diverges, and the CPU launcher vectorises across elements.
#pragma once

#include "kernels/core/hd.h"
#include "kernels/math/mat3.h"
#include "kernels/math/scalar.h"
#include "kernels/math/vec3.h"

namespace romp {

// Per-precision constants of the SVD (as Warp's svd config).
//
// Sweep counts were measured (Jacobi on AᵀA for 4 million random matrices, half of them with entries
// spread over 1e±2.6): the worst relative off-diagonal ‖offdiag(S)‖/tr S after 4, 5, 6, 7 sweeps was
// 3e-3, 3e-5, 2e-8, 2e-17. The approximate rotations of [McAdams] converge slowly only while angles
// are large (the fixed π/4 fallback); once the half-angle estimate is trusted the error drops
// roughly cubically per sweep, which is why double needs just one sweep more than float. Float
// needs 6 (with 5, one matrix in ~10⁵ misses the 1e-5 reconstruction bound of the tests), double 7
// (with 6, one in ~10⁴ misses 1e-12).
template <class T>
struct Svd3Config;

template <>
struct Svd3Config<float> {
  static constexpr int kJacobiSweeps = 6;
  // Magnitudes below this, in the normalised frame (largest entry of A in [1, 2)), are exact zeros:
  // Jacobi rotations by smaller half-angles are skipped, smaller off-diagonals of AᵀA are flushed,
  // and Givens / 2x2 steps on smaller vectors are the identity. 2^-30 ≈ 9e-10 is far below float's
  // ε = 1.2e-7, and a product of four such values (2^-120) is still a normal float. Without the flush
  // the converged late sweeps (off-diagonals down to 1e-20 and below) produce denormals, each a
  // microcode assist of 100+ cycles on x86 CPUs; the CPU batch was twice as slow.
  static constexpr float kNegligible = 9.3132257e-10f;  // 2^-30
  // Regularisation of the backward pass (see svd3_backward.h): gaps σᵢ ± σⱼ below this fraction of
  // |σ₀| are clamped to it. √ε of float: closer singular values are indistinguishable at the
  // forward pass's own accuracy, and 1/√ε bounds the gradient amplification.
  static constexpr float kGradientGapFloor = 3.4526698e-4f;  // 2^-11.5
};

template <>
struct Svd3Config<double> {
  static constexpr int kJacobiSweeps = 7;
  static constexpr double kNegligible = 5.5271478752604446e-76;       // 2^-250: ≪ ε = 1.1e-16, and 2^-1000 is normal
  static constexpr double kGradientGapFloor = 1.4901161193847656e-8;  // 2^-26
};

template <class T>
struct Svd3 {
  Mat3<T> U;      // proper rotation
  Vec3<T> sigma;  // σ₀ ≥ σ₁ ≥ |σ₂|; σ₂ < 0 exactly when det F < 0
  Mat3<T> V;      // proper rotation
};

template <class T>
struct Polar3 {
  Mat3<T> R;  // proper rotation U Vᵀ
  Mat3<T> S;  // symmetric V Σ Vᵀ; indefinite for inverted F
};

namespace svd_detail {

// tan²(3π/8) = 3 + 2√2 [McAdams, Alg. 2]: the approximate half-angle is trusted while it is below
// π/8, i.e. while γ sh² < ch²; beyond that the fixed rotation by π/4 (half-angle π/8) is used.
template <class T>
inline constexpr T kGamma = T(5.82842712474619009760);
template <class T>
inline constexpr T kCosPi8 = T(0.92387953251128675613);
template <class T>
inline constexpr T kSinPi8 = T(0.38268343236508977173);

// Rotation quaternion (w, x, y, z) that accumulates the Jacobi conjugations [McAdams, §2.3].
template <class T>
struct Quaternion {
  T w, v[3];
};

// x, or 0 when |x| < kNegligible (see Svd3Config).
template <class T>
ROMP_MATH_INLINE T flush_negligible(T x) {
  return math::select(math::abs(x) < Svd3Config<T>::kNegligible, T(0), x);
}

// One Jacobi conjugation S ← Qᵀ S Q that (approximately) zeroes S_pq, with (p, q, k) a cyclic
// permutation of (0, 1, 2) so that Q is the rotation about axis k by θ: Q_pp = Q_qq = cos θ,
// Q_qp = -Q_pq = sin θ. Exact Jacobi would take tan 2θ = 2 S_pq / (S_pp - S_qq); [McAdams, Alg. 2]
// approximates the half-angle by tan(θ/2) ≈ S_pq / (2 (S_pp - S_qq)), which needs one rsqrt.
template <int p, int q, class T>
ROMP_MATH_INLINE void jacobi_conjugate(Mat3<T>& S, Quaternion<T>& rotation) {
  constexpr int k = 3 - p - q;
  T ch = T(2) * (S.m[p][p] - S.m[q][q]);
  T sh = S.m[p][q];
  const bool approximate = kGamma<T> * sh * sh < ch * ch;
  const T omega = math::rsqrt(math::select(approximate, ch * ch + sh * sh, T(1)));
  ch = math::select(approximate, omega * ch, kCosPi8<T>);
  sh = math::select(approximate, omega * sh, kSinPi8<T>);
  // Rotations by negligible angles are skipped and negligible off-diagonals flushed (kNegligible).
  const bool negligible = math::abs(sh) < Svd3Config<T>::kNegligible;
  ch = math::select(negligible, T(1), ch);
  sh = math::select(negligible, T(0), sh);

  // Full-angle rotation from the half-angle: c = cos θ, s = sin θ.
  const T c = ch * ch - sh * sh;
  const T s = T(2) * ch * sh;
  const T a = S.m[p][p], b = S.m[p][q], d = S.m[q][q];
  const T e = S.m[p][k], f = S.m[q][k];
  S.m[p][p] = c * c * a + T(2) * c * s * b + s * s * d;
  S.m[q][q] = s * s * a - T(2) * c * s * b + c * c * d;
  S.m[p][q] = S.m[q][p] = flush_negligible((c * c - s * s) * b - c * s * (a - d));
  S.m[p][k] = S.m[k][p] = flush_negligible(c * e + s * f);
  S.m[q][k] = S.m[k][q] = flush_negligible(c * f - s * e);

  // rotation ← rotation ⊗ (ch, sh e_k): appends Q on the right, so V = Q₁ Q₂ Q₃ ...
  Quaternion<T> r = rotation;
  rotation.w = ch * r.w - sh * r.v[k];
  rotation.v[p] = ch * r.v[p] + sh * r.v[q];
  rotation.v[q] = ch * r.v[q] - sh * r.v[p];
  rotation.v[k] = ch * r.v[k] + sh * r.w;
}

// `sweeps` cyclic sweeps over the pairs (0,1), (1,2), (2,0), unrolled at compile time: the CPU
// batch loop vectorises only a loop body free of inner loops.
template <int sweeps, class T>
ROMP_MATH_INLINE void jacobi_sweeps(Mat3<T>& S, Quaternion<T>& rotation) {
  if constexpr (sweeps > 0) {
    jacobi_conjugate<0, 1>(S, rotation);
    jacobi_conjugate<1, 2>(S, rotation);
    jacobi_conjugate<2, 0>(S, rotation);
    jacobi_sweeps<sweeps - 1>(S, rotation);
  }
}

// The rotation matrix of a quaternion, normalised first (the accumulated product drifts from unit
// length by rounding only, but every ulp there would show up in Vᵀ V).
template <class T>
ROMP_MATH_INLINE Mat3<T> rotation_matrix(Quaternion<T> q) {
  const T scale = math::rsqrt(q.w * q.w + q.v[0] * q.v[0] + q.v[1] * q.v[1] + q.v[2] * q.v[2]);
  const T w = q.w * scale, x = q.v[0] * scale, y = q.v[1] * scale, z = q.v[2] * scale;
  return Mat3<T>(T(1) - T(2) * (y * y + z * z), T(2) * (x * y - w * z), T(2) * (x * z + w * y), T(2) * (x * y + w * z),
                 T(1) - T(2) * (x * x + z * z), T(2) * (y * z - w * x), T(2) * (x * z - w * y), T(2) * (y * z + w * x),
                 T(1) - T(2) * (x * x + y * y));
}

// When `condition` holds, columns (i, j) of M become (column j, -column i): a swap that keeps det M.
template <int i, int j, class T>
ROMP_MATH_INLINE void swap_columns_keep_orientation(bool condition, Mat3<T>& M) {
  for (int r = 0; r < 3; ++r) {
    const T column_i = M.m[r][i];
    M.m[r][i] = math::select(condition, M.m[r][j], column_i);
    M.m[r][j] = math::select(condition, -column_i, M.m[r][j]);
  }
}

// Orders columns i < j of B (and V alike, so B = A V still holds) by decreasing norm [McAdams, Alg. 3].
template <int i, int j, class T>
ROMP_MATH_INLINE void sort_column_pair(Mat3<T>& B, Mat3<T>& V, Vec3<T>& squared_norms) {
  const bool swap = squared_norms[i] < squared_norms[j];
  swap_columns_keep_orientation<i, j>(swap, B);
  swap_columns_keep_orientation<i, j>(swap, V);
  math::swap_if(swap, squared_norms[i], squared_norms[j]);
}

// Givens rotation G on rows (p, q) of B that zeroes B_qp and leaves B_pp = √(B_pp² + B_qp²) ≥ 0, in
// the half-angle form of [McAdams, Alg. 4]: the half-angle vector (|a₁| + ρ, a₂) needs no division,
// and the swap for a₁ < 0 turns the rotation by the angle of (|a₁|, a₂) into the one for (a₁, a₂).
// U accumulates Gᵀ, so that (U)(G B) = (previous U) B at every step.
template <int p, int q, class T>
ROMP_MATH_INLINE void givens_qr_step(Mat3<T>& B, Mat3<T>& U) {
  const T a1 = B.m[p][p];
  const T a2 = B.m[q][p];
  const T rho = math::sqrt(a1 * a1 + a2 * a2);
  T sh = math::select(rho > Svd3Config<T>::kNegligible, a2, T(0));
  T ch = math::abs(a1) + math::max(rho, Svd3Config<T>::kNegligible);
  math::swap_if(a1 < T(0), sh, ch);
  const T omega = math::rsqrt(ch * ch + sh * sh);
  ch *= omega;
  sh *= omega;
  const T c = ch * ch - sh * sh;
  const T s = T(2) * ch * sh;
  // Columns left of p are already zero in rows p and q.
  for (int column = p; column < 3; ++column) {
    const T bp = B.m[p][column], bq = B.m[q][column];
    B.m[p][column] = c * bp + s * bq;
    B.m[q][column] = c * bq - s * bp;
  }
  for (int r = 0; r < 3; ++r) {
    const T up = U.m[r][p], uq = U.m[r][q];
    U.m[r][p] = c * up + s * uq;
    U.m[r][q] = c * uq - s * up;
  }
}

// Unit vector along (x, y), or (1, 0) when (x, y) is too small to normalise.
template <class T>
ROMP_MATH_INLINE void normalise_or_unit_x(T& x, T& y) {
  const T squared = x * x + y * y;
  const bool usable = squared > Svd3Config<T>::kNegligible * Svd3Config<T>::kNegligible;
  const T scale = math::rsqrt(math::select(usable, squared, T(1)));
  x = math::select(usable, x * scale, T(1));
  y = math::select(usable, y * scale, T(0));
}

// Columns (1, 2) of M times the rotation [[c, -s], [s, c]].
template <class T>
ROMP_MATH_INLINE void rotate_trailing_columns(Mat3<T>& M, T c, T s) {
  for (int r = 0; r < 3; ++r) {
    const T m1 = M.m[r][1], m2 = M.m[r][2];
    M.m[r][1] = c * m1 + s * m2;
    M.m[r][2] = c * m2 - s * m1;
  }
}

// Step 4: exact SVD of R's trailing block [[a, b], [0, d]] = Ub diag(λ₁, λ₂) Vbᵀ, folded into U and V.
// A left rotation G makes G M symmetric with trace ρ = |(a + d, b)| ≥ 0; its eigenvalues are then
// (ρ ± h)/2 with h = √((p - r)² + 4 q²), so λ₁ ≥ |λ₂| and sign λ₂ = sign det M hold by construction.
// The eigenvector of λ₁ is read from whichever column of (G M - λ₂ I) is free of cancellation.
template <class T>
ROMP_MATH_INLINE void trailing_block_svd(const Mat3<T>& R, Mat3<T>& U, Mat3<T>& V, T& lambda1, T& lambda2) {
  const T a = R.m[1][1], b = R.m[1][2], d = R.m[2][2];
  // G = [[gc, gs], [-gs, gc]] with (gc, gs) ∝ (a + d, -b).
  T gc = a + d, gs = -b;
  const T rho = math::sqrt(gc * gc + gs * gs);
  normalise_or_unit_x(gc, gs);
  // G M = [[p, q], [q, r]].
  const T p = gc * a;
  const T q = -gs * a;
  const T r = gc * d - gs * b;
  const T diff = p - r;
  const T h = math::sqrt(diff * diff + T(4) * q * q);
  lambda1 = T(0.5) * (rho + h);
  lambda2 = T(0.5) * (rho - h);
  const bool first_column = diff >= T(0);
  T jc = math::select(first_column, diff + h, T(2) * q);
  T js = math::select(first_column, T(2) * q, h - diff);
  normalise_or_unit_x(jc, js);
  // M = Gᵀ J Λ Jᵀ: Vb = J, Ub = Gᵀ J, both rotations [[c, -s], [s, c]].
  rotate_trailing_columns(U, gc * jc - gs * js, gs * jc + gc * js);
  rotate_trailing_columns(V, jc, js);
}

// Step 5: compare-exchange of singular values i < j (σᵢ ≥ 0) so that σᵢ ≥ |σⱼ|, moving the sign of σⱼ
// along: columns swap in U and V, and the signs are chosen so that both keep det = +1 and every
// term σ u vᵀ is unchanged.
template <int i, int j, class T>
ROMP_MATH_INLINE void order_singular_pair(Mat3<T>& U, Vec3<T>& sigma, Mat3<T>& V) {
  const bool swap = sigma[i] < math::abs(sigma[j]);
  const T sign_j = math::sign(sigma[j]);
  for (int r = 0; r < 3; ++r) {
    const T ui = U.m[r][i], uj = U.m[r][j], vi = V.m[r][i], vj = V.m[r][j];
    U.m[r][i] = math::select(swap, sign_j * uj, ui);
    U.m[r][j] = math::select(swap, -sign_j * ui, uj);
    V.m[r][i] = math::select(swap, vj, vi);
    V.m[r][j] = math::select(swap, -vi, vj);
  }
  const T si = sigma[i], sj = sigma[j];
  sigma[i] = math::select(swap, math::abs(sj), si);
  sigma[j] = math::select(swap, sign_j * si, sj);
}

}  // namespace svd_detail

// F = U diag(σ) Vᵀ with U, V proper rotations, σ₀ ≥ σ₁ ≥ |σ₂| and sign σ₂ = sign det F.
template <class T>
ROMP_MATH_INLINE Svd3<T> svd3(const Mat3<T>& F) {
  using namespace svd_detail;
  // Step 0: exact power-of-two normalisation.
  const math::PowerOfTwoScale<T> scale = math::power_of_two_scale(max_abs(F));
  const Mat3<T> A = F * scale.down;

  // Step 1: Jacobi on the symmetric AᵀA.
  Mat3<T> S = transpose_times(A, A);
  Quaternion<T> rotation{T(1), {T(0), T(0), T(0)}};
  jacobi_sweeps<Svd3Config<T>::kJacobiSweeps>(S, rotation);
  Mat3<T> V = rotation_matrix(rotation);

  // Step 2: B = A V with columns by decreasing norm.
  Mat3<T> B = A * V;
  Vec3<T> squared_norms(squared_norm(B.column(0)), squared_norm(B.column(1)), squared_norm(B.column(2)));
  sort_column_pair<0, 1>(B, V, squared_norms);
  sort_column_pair<0, 2>(B, V, squared_norms);
  sort_column_pair<1, 2>(B, V, squared_norms);

  // Step 3: B = U R.
  Mat3<T> U = Mat3<T>::identity();
  givens_qr_step<0, 1>(B, U);
  givens_qr_step<0, 2>(B, U);
  givens_qr_step<1, 2>(B, U);

  // Step 4: diagonalise R's trailing block; step 5: exact order.
  Vec3<T> sigma;
  sigma[0] = B.m[0][0];
  trailing_block_svd(B, U, V, sigma[1], sigma[2]);
  order_singular_pair<0, 1>(U, sigma, V);
  order_singular_pair<1, 2>(U, sigma, V);

  return {U, sigma * scale.up, V};
}

// F = R S with R = U Vᵀ a proper rotation and S = V Σ Vᵀ symmetric (negative eigenvalue when det F < 0).
template <class T>
ROMP_MATH_INLINE Polar3<T> polar3(const Mat3<T>& F) {
  const Svd3<T> svd = svd3(F);
  const Mat3<T> V_sigma = svd.V * Mat3<T>::diag(svd.sigma);
  return {times_transpose(svd.U, svd.V), times_transpose(V_sigma, svd.V)};
}

}  // namespace romp
