// One point of the fused deformation-map evaluation, as a device function that other kernels call too
// (the batch evaluator, the inversion of g for Eulerian quadrature). See deformation_map_eval.h.
#pragma once

#include <cmath>

#include "kernels/core/hd.h"
#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"
#include "kernels/rom/deformation_map_eval.h"

namespace romp::rom {

namespace map_point_detail {
inline constexpr int kMaxInputs = kMaxMapLatent + 3;
inline constexpr int kMaxUnits = kMaxMapWidth > kMaxInputs ? kMaxMapWidth : kMaxInputs;

template <class T>
ROMP_HD_INLINE int inputs_of(const DeformationMapView<T>& map, int layer) {
  return layer == 0 ? map.latent + 3 : map.width;
}
template <class T>
ROMP_HD_INLINE int outputs_of(const DeformationMapView<T>& map, int layer) {
  return layer == map.hidden_layers ? 3 : map.width;
}
}  // namespace map_point_detail

// x = g(X; x̂) and, when F or dg_dxhat is not null, F = ∇_X g and ∂g_o/∂x̂_j written to
// dg_dxhat[(o r + j) dg_stride]. The caller has checked the map's sizes against the kernel limits.
template <class T>
ROMP_HD void evaluate_map_point(const DeformationMapView<T>& map, const T* xhat, const Vec3<T>& X, Vec3<T>& x,
                                Mat3<T>* F, T* dg_dxhat, Index dg_stride) {
  using namespace map_point_detail;
  T a[kMaxUnits], z[kMaxUnits];
  for (int j = 0; j < map.latent; ++j) a[j] = xhat[j];
  for (int c = 0; c < 3; ++c) a[map.latent + c] = (X[c] - map.X_min[c]) * map.X_scale[c];

  // Forward: z = W a + b per layer; the hidden layers' ELU slopes are kept for the reverse sweeps.
  T slope[kMaxMapHiddenLayers][kMaxMapWidth];
  const T* layer_start = map.parameters.data();
  for (int k = 0; k <= map.hidden_layers; ++k) {
    const int in = inputs_of(map, k), n_out = outputs_of(map, k);
    const T* W = layer_start;
    const T* b = W + n_out * in;
    for (int o = 0; o < n_out; ++o) {
      T sum = T(0);
      ROMP_SIMD_SUM(sum)
      for (int j = 0; j < in; ++j) sum += W[o * in + j] * a[j];
      z[o] = b[o] + sum;
    }
    if (k < map.hidden_layers) {
      for (int o = 0; o < n_out; ++o) {
        const T e = z[o] > T(0) ? T(0) : T(std::exp(z[o]));  // ELU(z) = e^z − 1 and ELU'(z) = e^z for z ≤ 0
        a[o] = z[o] > T(0) ? z[o] : e - T(1);
        slope[k][o] = z[o] > T(0) ? T(1) : e;
      }
    }
    layer_start = b + n_out;
  }
  for (int c = 0; c < 3; ++c) x[c] = X[c] + map.u_mean[c] + map.u_std[c] * z[c];
  if (!F && !dg_dxhat) return;

  // Reverse: row o of ∂out/∂[x̂, X̄] = e_oᵀ W_H D_{H−1} W_{H−1} ⋯ D_0 W_0.
  Mat3<T> gradient = Mat3<T>::identity();
  for (int o = 0; o < 3; ++o) {
    // `row` is ∂out_o/∂z_k over layer k's pre-activations z_k; at k = H it is e_o.
    T row[kMaxUnits], next[kMaxUnits];
    row[0] = T(1);
    const T* layer_end = map.parameters.data() + map.parameters.size();
    for (int k = map.hidden_layers; k >= 0; --k) {
      const int in = inputs_of(map, k), n_out = outputs_of(map, k);
      const T* b = layer_end - n_out;
      const T* W = b - n_out * in;
      // rowᵀ W, then the slopes of layer k − 1's ELU; at k = H, e_oᵀ W is W's row o.
      const int first = k == map.hidden_layers ? o : 0, count = k == map.hidden_layers ? 1 : n_out;
      // Row by row of W, so the inner loop runs along W's contiguous rows (it vectorises on the CPU); each
      // next[j] still sums over q in order.
      for (int j = 0; j < in; ++j) next[j] = T(0);
      for (int q = 0; q < count; ++q) {
        const T weight = row[q];
        const T* W_row = W + (first + q) * in;
        for (int j = 0; j < in; ++j) next[j] += weight * W_row[j];
      }
      for (int j = 0; j < in; ++j) row[j] = k > 0 ? next[j] * slope[k - 1][j] : next[j];
      layer_end = W;
    }
    for (int c = 0; c < 3; ++c) gradient(o, c) += map.u_std[o] * row[map.latent + c] * map.X_scale[c];
    if (dg_dxhat)
      for (int j = 0; j < map.latent; ++j) dg_dxhat[(o * map.latent + j) * dg_stride] = map.u_std[o] * row[j];
  }
  if (F) *F = gradient;
}

}  // namespace romp::rom
