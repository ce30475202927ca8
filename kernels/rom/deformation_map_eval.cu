// The fused deformation-map kernel: one forward sweep keeping the ELU slopes, then three reverse sweeps
// for the rows of the Jacobian (see deformation_map_eval.h).
#include "kernels/rom/deformation_map_eval.h"

#include <cmath>
#include <string>

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"

namespace romp::rom {
namespace {

constexpr int kMaxInputs = kMaxMapLatent + 3;
constexpr int kMaxUnits = kMaxMapWidth > kMaxInputs ? kMaxMapWidth : kMaxInputs;

template <class T>
struct MapPoint {
  DeformationMapView<T> map;
  const T* xhat;
  Vec3Planes<const T> X;
  DeformationMapOutputs<T> out;

  ROMP_HD int inputs_of(int layer) const { return layer == 0 ? map.latent + 3 : map.width; }
  ROMP_HD int outputs_of(int layer) const { return layer == map.hidden_layers ? 3 : map.width; }

  ROMP_HD void operator()(Index i) const {
    const Vec3<T> X_i = X.load(i);
    T a[kMaxUnits], z[kMaxUnits];
    for (int j = 0; j < map.latent; ++j) a[j] = xhat[j];
    for (int c = 0; c < 3; ++c) a[map.latent + c] = (X_i[c] - map.X_min[c]) * map.X_scale[c];

    // Forward: z = W a + b per layer; the hidden layers' ELU slopes are kept for the reverse sweeps.
    T slope[kMaxMapHiddenLayers][kMaxMapWidth];
    const T* layer_start = map.parameters.data();
    for (int k = 0; k <= map.hidden_layers; ++k) {
      const int in = inputs_of(k), n_out = outputs_of(k);
      const T* W = layer_start;
      const T* b = W + n_out * in;
      for (int o = 0; o < n_out; ++o) {
        T sum = b[o];
        for (int j = 0; j < in; ++j) sum += W[o * in + j] * a[j];
        z[o] = sum;
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
    if (out.x.data()) {
      Vec3<T> x;
      for (int c = 0; c < 3; ++c) x[c] = X_i[c] + map.u_mean[c] + map.u_std[c] * z[c];
      out.x.store(i, x);
    }
    if (!out.F.data() && !out.dg_dxhat.data()) return;

    // Reverse: row o of ∂out/∂[x̂, X̄] = e_oᵀ W_H D_{H−1} W_{H−1} ⋯ D_0 W_0.
    Mat3<T> F = Mat3<T>::identity();
    for (int o = 0; o < 3; ++o) {
      // `row` is ∂out_o/∂z_k over layer k's pre-activations z_k; at k = H it is e_o.
      T row[kMaxUnits], next[kMaxUnits];
      row[0] = T(1);
      const T* layer_end = map.parameters.data() + map.parameters.size();
      for (int k = map.hidden_layers; k >= 0; --k) {
        const int in = inputs_of(k), n_out = outputs_of(k);
        const T* b = layer_end - n_out;
        const T* W = b - n_out * in;
        // rowᵀ W, then the slopes of layer k − 1's ELU; at k = H, e_oᵀ W is W's row o.
        const int first = k == map.hidden_layers ? o : 0, count = k == map.hidden_layers ? 1 : n_out;
        for (int j = 0; j < in; ++j) {
          T sum = T(0);
          for (int q = 0; q < count; ++q) sum += row[q] * W[(first + q) * in + j];
          next[j] = k > 0 ? sum * slope[k - 1][j] : sum;
        }
        for (int j = 0; j < in; ++j) row[j] = next[j];
        layer_end = W;
      }
      for (int c = 0; c < 3; ++c) F(o, c) += map.u_std[o] * row[map.latent + c] * map.X_scale[c];
      if (out.dg_dxhat.data()) {
        const Index n = X.count();
        for (int j = 0; j < map.latent; ++j) out.dg_dxhat[(o * map.latent + j) * n + i] = map.u_std[o] * row[j];
      }
    }
    if (out.F.data()) out.F.store(i, F);
  }
};

}  // namespace

Index deformation_map_parameter_count(int latent, int hidden_layers, int width) {
  Index count = 0;
  for (int k = 0; k <= hidden_layers; ++k) {
    const Index in = k == 0 ? latent + 3 : width, n_out = k == hidden_layers ? 3 : width;
    count += n_out * in + n_out;
  }
  return count;
}

template <class T>
void evaluate_deformation_map(const Exec& exec, const DeformationMapView<T>& map, Span<const T> xhat,
                              Vec3Planes<const T> X, const DeformationMapOutputs<T>& out) {
  ROMP_CHECK(map.latent >= 1 && map.latent <= kMaxMapLatent,
             "the fused map evaluator takes a latent size r in [1, " + std::to_string(kMaxMapLatent) + "], got " +
                 std::to_string(map.latent));
  ROMP_CHECK(map.hidden_layers >= 0 && map.hidden_layers <= kMaxMapHiddenLayers,
             "the fused map evaluator takes 0 to " + std::to_string(kMaxMapHiddenLayers) + " hidden layers, got " +
                 std::to_string(map.hidden_layers));
  ROMP_CHECK(map.hidden_layers == 0 || (map.width >= 1 && map.width <= kMaxMapWidth),
             "the fused map evaluator takes hidden layers of 1 to " + std::to_string(kMaxMapWidth) + " units, got " +
                 std::to_string(map.width));
  ROMP_CHECK(map.parameters.size() == deformation_map_parameter_count(map.latent, map.hidden_layers, map.width),
             "the map's parameter buffer holds " + std::to_string(map.parameters.size()) + " values, its sizes need " +
                 std::to_string(deformation_map_parameter_count(map.latent, map.hidden_layers, map.width)));
  ROMP_CHECK(xhat.size() == map.latent, "x̂ must hold r = " + std::to_string(map.latent) + " values");
  const Index n = X.count();
  ROMP_CHECK(!out.x.data() || out.x.count() == n, "x must hold one vector per point");
  ROMP_CHECK(!out.F.data() || out.F.count() == n, "F must hold one matrix per point");
  ROMP_CHECK(!out.dg_dxhat.data() || out.dg_dxhat.size() == 3 * map.latent * n, "dg_dxhat must hold 3 r planes of n");
  if (n == 0) return;
  for_each(exec, n, MapPoint<T>{map, xhat.data(), X, out});
}

template void evaluate_deformation_map<float>(const Exec&, const DeformationMapView<float>&, Span<const float>,
                                              Vec3Planes<const float>, const DeformationMapOutputs<float>&);
template void evaluate_deformation_map<double>(const Exec&, const DeformationMapView<double>&, Span<const double>,
                                               Vec3Planes<const double>, const DeformationMapOutputs<double>&);

}  // namespace romp::rom
