// The deformation map at one point for a network whose sizes are compile-time constants: the same
// arithmetic as evaluate_map_point (deformation_map_point.h, the reference), built so that nothing of a
// GPU thread's work lives in local memory.
//
// Why it is fast on the GPU. With the sizes known, every loop unrolls and every array (activations, ELU
// slopes, the reverse sweep's row) is indexed by constants, so it stays in registers: no stack frame
// (the generic kernel keeps 3 KB per thread in local memory). The weights travel by value in the kernel's
// launch parameters (FixedMapWeights, about 16 KB for the paper's map; CUDA 12.1 allows 32 KB on sm_70
// and later), so each multiply reads its weight as a constant-bank operand: no load instruction, one
// broadcast for the whole warp, nothing to stage in shared memory, and nothing shared between launches
// (graph capture and concurrent streams stay safe). ptxas for sm_90 (CUDA 13.0): the batch kernel
// (MapPoint) 254 registers, no stack; the generic one 3,504 bytes of stack.
#pragma once

#include <cmath>

#include "kernels/core/hd.h"
#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"
#include "kernels/rom/deformation_map_eval.h"

namespace romp::rom {

// The sizes of a map with latent size R, H hidden layers of W units; layer k's parameters (weight
// [out(k) × in(k)] row-major, then bias [out(k)]) start at offset(k) of the packed buffer.
template <int R, int H, int W>
struct MapShape {
  static constexpr int kLatent = R, kHiddenLayers = H, kWidth = W;
  static constexpr int in(int k) { return k == 0 ? R + 3 : W; }
  static constexpr int out(int k) { return k == H ? 3 : W; }
  static constexpr int offset(int k) {
    int start = 0;
    for (int layer = 0; layer < k; ++layer) start += out(layer) * in(layer) + out(layer);
    return start;
  }
  static constexpr int kParameters = offset(H + 1);
  static constexpr int kUnits = W > R + 3 ? W : R + 3;  // the widest layer input or output
};

// A map of shape S with its parameters by value and its normalisation.
template <class T, class S>
struct FixedMapWeights {
  T parameters[S::kParameters];
  Vec3<T> X_min, X_scale, u_mean, u_std;
};

namespace fixed_map_detail {

// Between the sweeps of one evaluation (MEMBAR.CTA on the device, nothing on the host). Every hidden
// weight is an operand of the forward sweep and of each reverse sweep; without a fence ptxas loads each
// once into a register and keeps it for the next sweep, thousands of live values, and spills them
// (14.6 KB per thread in a loop of evaluations, sm_90). Across a fence it reads each weight again as a
// constant-bank operand. The fence orders this thread's memory accesses only, and a sweep makes none.
ROMP_HD_INLINE void sweep_fence() {
#if defined(__CUDA_ARCH__)
  __threadfence_block();
#endif
}

// Layer K and the ones after it: z = W a + b; hidden layers store ELU(z) in `a` and its slope.
template <int K, class T, class S>
ROMP_HD_INLINE void forward(const T* p, T* a, T* z, T (*slope)[S::kWidth]) {
  constexpr int in = S::in(K), n_out = S::out(K), start = S::offset(K);
  ROMP_UNROLL
  for (int o = 0; o < n_out; ++o) {
    T sum = p[start + n_out * in + o];
    ROMP_UNROLL
    for (int j = 0; j < in; ++j) sum += p[start + o * in + j] * a[j];
    z[o] = sum;
  }
  if constexpr (K < S::kHiddenLayers) {
    ROMP_UNROLL
    for (int o = 0; o < n_out; ++o) {
      const T e = z[o] > T(0) ? T(0) : T(std::exp(z[o]));  // ELU(z) = e^z − 1 and ELU'(z) = e^z for z ≤ 0
      a[o] = z[o] > T(0) ? z[o] : e - T(1);
      slope[K][o] = z[o] > T(0) ? T(1) : e;
    }
    forward<K + 1, T, S>(p, a, z, slope);
  }
}

// `row` holds ∂out_o/∂z_K on entry; on return ∂out_o/∂[x̂, X̄] (the inputs of layer 0).
template <int K, class T, class S>
ROMP_HD_INLINE void reverse(const T* p, T* row, const T (*slope)[S::kWidth]) {
  constexpr int in = S::in(K), n_out = S::out(K), start = S::offset(K);
  T next[in];
  ROMP_UNROLL
  for (int j = 0; j < in; ++j) {
    T sum = T(0);
    ROMP_UNROLL
    for (int q = 0; q < n_out; ++q) sum += row[q] * p[start + q * in + j];
    if constexpr (K > 0) sum *= slope[K - 1][j];
    next[j] = sum;
  }
  ROMP_UNROLL
  for (int j = 0; j < in; ++j) row[j] = next[j];
  if constexpr (K > 0) reverse<K - 1, T, S>(p, row, slope);
}

}  // namespace fixed_map_detail

// x = g(X; x̂) and, when `jacobian`, F = ∇_X g and each ∂g_o/∂x̂_j handed to dg_dxhat(o, j, value): the
// results of evaluate_map_point, for a map of shape S (H ≥ 1). Flags and a callback rather than output
// pointers: a pointer to a local that may be null makes the local addressable, and so local memory.
template <class T, class S, class DgSink>
ROMP_HD void evaluate_fixed_map_point(const FixedMapWeights<T, S>& map, const T* xhat, const Vec3<T>& X, Vec3<T>& x,
                                      Mat3<T>& F, bool jacobian, const DgSink& dg_dxhat) {
  constexpr int R = S::kLatent, H = S::kHiddenLayers;
  static_assert(H >= 1, "the linear baseline has its own closed form; the generic evaluator serves it");
  const T* p = map.parameters;
  T a[S::kUnits], z[S::kUnits];
  T slope[H][S::kWidth];
  ROMP_UNROLL
  for (int j = 0; j < R; ++j) a[j] = xhat[j];
  ROMP_UNROLL
  for (int c = 0; c < 3; ++c) a[R + c] = (X[c] - map.X_min[c]) * map.X_scale[c];
  fixed_map_detail::forward<0, T, S>(p, a, z, slope);
  ROMP_UNROLL
  for (int c = 0; c < 3; ++c) x[c] = X[c] + map.u_mean[c] + map.u_std[c] * z[c];
  if (!jacobian) return;

  // Reverse: row o of ∂out/∂[x̂, X̄] = e_oᵀ W_H D_{H−1} W_{H−1} ⋯ D_0 W_0, one output row at a time (the
  // rows in turn, not unrolled together: three rows at once would need three times the registers).
  ROMP_NO_UNROLL
  for (int o = 0; o < 3; ++o) {
    constexpr int in_H = S::in(H), start_H = S::offset(H);
    T row[S::kUnits];
    fixed_map_detail::sweep_fence();
    ROMP_UNROLL
    for (int j = 0; j < in_H; ++j) row[j] = p[start_H + o * in_H + j] * slope[H - 1][j];
    fixed_map_detail::reverse<H - 1, T, S>(p, row, slope);
    ROMP_UNROLL
    for (int c = 0; c < 3; ++c) {
      const T entry = T(o == c) + map.u_std[o] * row[R + c] * map.X_scale[c];
      // Selected by value, not F(o, c) = entry: a runtime row index would put F in local memory.
      F(0, c) = o == 0 ? entry : F(0, c);
      F(1, c) = o == 1 ? entry : F(1, c);
      F(2, c) = o == 2 ? entry : F(2, c);
    }
    ROMP_UNROLL
    for (int j = 0; j < R; ++j) dg_dxhat(o, j, map.u_std[o] * row[j]);
  }
}

}  // namespace romp::rom
