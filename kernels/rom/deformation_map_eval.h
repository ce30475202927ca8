// The fused evaluator of the ROM's deformation map: g(X, x̂), ∇_X g and ∂g/∂x̂ for a batch of material
// points in one kernel, straight from the model's weights (ROM paper, Sec. 3-4; model file layout in
// nn/rom/rom_model_file.h).
//
// The map is an MLP on [x̂ (r), X̄ (3)], X̄ = (X − X_min) ⊙ X_scale (X_scale = 1 / (X_max − X_min)):
// H hidden layers of `width` units with ELU (α = 1), then a linear layer to a standardised displacement
// out (3), and x = X + u_mean + u_std ⊙ out. H = 0 is the linear baseline (one affine layer).
//
// Derivatives. The online stage needs the full Jacobian ∂out/∂[x̂, X̄] (3 × (r + 3)) at every point. A
// forward-mode pass carries r + 3 tangents through every layer; the reverse mode carries the 3 output
// rows back instead, after one forward pass that keeps each hidden layer's ELU slope. Both give the
// same exact Jacobian; reverse mode costs 1 + 3 matrix-vector sweeps per point instead of 1 + r + 3
// (4 against 10 at the paper's r = 6), so it is what the kernels do, one thread per point. The generic
// kernel (deformation_map_point.h) takes any sizes and keeps its per-point arrays in thread-local
// memory; the fixed-shape kernels (fixed_map_point.h) keep them in registers.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/core/exec.h"
#include "kernels/core/hd.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/math/vec3.h"

namespace romp::rom {

// Sizes the kernel's per-point scratch is built for (the paper's map: H = 5, width 30, r ≤ 16).
inline constexpr int kMaxMapWidth = 64;
inline constexpr int kMaxMapHiddenLayers = 8;
inline constexpr int kMaxMapLatent = 32;

// The weights of g, in one buffer on the evaluating backend: for each layer k = 0 .. H its weight
// [out_k × in_k] (row-major) and then its bias [out_k], with in_0 = r + 3 (x̂ first, then X̄),
// out_k = width for k < H and out_H = 3.
template <class T>
struct DeformationMapView {
  int latent = 0;         // r
  int hidden_layers = 0;  // H
  int width = 0;          // units per hidden layer (unused when H = 0)
  Span<const T> parameters;
  // The same parameters on the host, or null. Given, the kernels for the network sizes they are built
  // for (fixed_map_point.h) carry them in their launch parameters; without, the generic kernel runs.
  const T* host_parameters = nullptr;
  Vec3<T> X_min = Vec3<T>::zero(), X_scale = Vec3<T>::zero();
  Vec3<T> u_mean = Vec3<T>::zero(), u_std = Vec3<T>::zero();
};

// The number of scalars in `parameters` for a map of these sizes.
Index deformation_map_parameter_count(int latent, int hidden_layers, int width);

// A map's sizes, packed parameters and normalisation on the host, as a model file provides them; the
// owner uploads `parameters` and points a DeformationMapView at them.
struct DeformationMapWeights {
  int latent = 0, hidden_layers = 0, width = 0;
  std::vector<float> parameters;
  Vec3<float> X_min = Vec3<float>::zero(), X_scale = Vec3<float>::zero();
  Vec3<float> u_mean = Vec3<float>::zero(), u_std = Vec3<float>::zero();
};

// The view of `weights` whose parameters are `parameters`, their copy on the evaluating backend.
inline DeformationMapView<float> map_view(const DeformationMapWeights& weights, Span<const float> parameters) {
  DeformationMapView<float> view;
  view.latent = weights.latent;
  view.hidden_layers = weights.hidden_layers;
  view.width = weights.width;
  view.parameters = parameters;
  view.host_parameters = weights.parameters.data();
  view.X_min = weights.X_min;
  view.X_scale = weights.X_scale;
  view.u_mean = weights.u_mean;
  view.u_std = weights.u_std;
  return view;
}

// Outputs for n points. Any of the three may be left empty (null data) to skip it; the Jacobian is
// computed only when F or dg_dxhat is asked for.
template <class T>
struct DeformationMapOutputs {
  Vec3Planes<T> x;   // g(X, x̂), m
  Mat3Planes<T> F;   // ∇_X g
  Span<T> dg_dxhat;  // ∂g/∂x̂: 3 r planes of n, plane (o r + j) = ∂g_o/∂x̂_j
};

// Which kernel evaluates the map.
enum class MapKernel {
  // On CUDA the fixed-shape kernel where the map's sizes have one (fixed_map_point.h: the papers'
  // network, float, with the view's host parameters); elsewhere the generic kernel, also on the CPU,
  // where its vectorised loops run 1.4–1.6× faster than the fixed-shape ones (romp-bench --suite mlp).
  Fastest,
  // The fixed-shape kernel; an error where the map's sizes have none or the view has no host parameters.
  Fixed,
  // The generic kernel: any sizes within the limits, and the reference the others are tested against.
  Generic,
};

// Evaluates g at X (n points, planes on exec's backend) for one shared x̂ (`latent` values on exec's
// backend); with `live`, a count on exec's backend, at the first live[0] points only (for_each_bounded: n is
// then a bound). Throws romp::Error when the sizes exceed the kernel's limits or the views disagree.
// Queued on exec like for_each. Instantiated for float and double.
template <class T>
void evaluate_deformation_map(const Exec& exec, const DeformationMapView<T>& map, Span<const T> xhat,
                              Vec3Planes<const T> X, const DeformationMapOutputs<T>& out,
                              MapKernel kernel = MapKernel::Fastest, Span<const std::int64_t> live = {});

}  // namespace romp::rom
