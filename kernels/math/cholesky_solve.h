// Solves small symmetric positive (semi-)definite systems in place, for the ROM's r × r projections.
#pragma once

#include <cmath>

#include "kernels/core/hd.h"

namespace romp {

// Relative diagonal shift: A + δ max(diag A) I with δ = 1e-12 keeps Cholesky defined when the points
// of a projection leave a latent direction unconstrained (then y is close to the minimum-norm
// solution in that direction) and changes a well-posed solution by about δ times its condition number.
inline constexpr double kCholeskyShift = 1e-12;

// Solves A y = c for y, overwriting c with y and A with its Cholesky factor (row-major, n × n). Returns
// false when A is not positive semi-definite (a pivot ≤ 0 after the shift) or has no positive diagonal.
template <class T>
ROMP_HD bool cholesky_solve(int n, T* A, T* c) {
  T largest = T(0);
  for (int i = 0; i < n; ++i) largest = A[i * n + i] > largest ? A[i * n + i] : largest;
  if (!(largest > T(0))) return false;
  const T shift = T(kCholeskyShift) * largest;
  for (int i = 0; i < n; ++i) A[i * n + i] += shift;
  for (int j = 0; j < n; ++j) {
    T pivot = A[j * n + j];
    for (int k = 0; k < j; ++k) pivot -= A[j * n + k] * A[j * n + k];
    if (!(pivot > T(0))) return false;
    const T diagonal = std::sqrt(pivot);
    A[j * n + j] = diagonal;
    for (int i = j + 1; i < n; ++i) {
      T value = A[i * n + j];
      for (int k = 0; k < j; ++k) value -= A[i * n + k] * A[j * n + k];
      A[i * n + j] = value / diagonal;
    }
  }
  for (int i = 0; i < n; ++i) {  // L z = c
    for (int k = 0; k < i; ++k) c[i] -= A[i * n + k] * c[k];
    c[i] /= A[i * n + i];
  }
  for (int i = n - 1; i >= 0; --i) {  // Lᵀ y = z
    for (int k = i + 1; k < n; ++k) c[i] -= A[k * n + i] * c[k];
    c[i] /= A[i * n + i];
  }
  return true;
}

}  // namespace romp
