// The two ways a kernel evaluates the deformation map at a point, behind one call, and the choice
// between them from the map's sizes (see fixed_map_point.h for why the fixed-shape one is fast).
#pragma once

#include <string>
#include <tuple>
#include <type_traits>

#include "kernels/core/error.h"
#include "kernels/core/exec.h"
#include "kernels/core/hd.h"
#include "kernels/rom/deformation_map_point.h"
#include "kernels/rom/fixed_map_point.h"

namespace romp::rom {

// Both evaluators: x = g(X; x̂) and, when `jacobian`, F = ∇_X g and dg_dxhat(o, j, ∂g_o/∂x̂_j) for every
// o < 3, j < r (a no-op callable where ∂g/∂x̂ is not wanted).

// Any sizes within the kernel limits, read at run time from the view (weights in global memory).
template <class T>
struct GenericMapEvaluator {
  DeformationMapView<T> map;
  ROMP_HD int latent() const { return map.latent; }
  template <class DgSink>
  ROMP_HD void operator()(const T* xhat, const Vec3<T>& X, Vec3<T>& x, Mat3<T>& F, bool jacobian,
                          const DgSink& dg_dxhat) const {
    T dg[3 * kMaxMapLatent];
    evaluate_map_point(map, xhat, X, x, jacobian ? &F : nullptr, jacobian ? dg : nullptr, 1);
    if (!jacobian) return;
    for (int o = 0; o < 3; ++o)
      for (int j = 0; j < map.latent; ++j) dg_dxhat(o, j, dg[o * map.latent + j]);
  }
};

// One shape S, its weights by value.
template <class T, class S>
struct FixedMapEvaluator {
  FixedMapWeights<T, S> map;
  ROMP_HD int latent() const { return S::kLatent; }
  template <class DgSink>
  ROMP_HD void operator()(const T* xhat, const Vec3<T>& X, Vec3<T>& x, Mat3<T>& F, bool jacobian,
                          const DgSink& dg_dxhat) const {
    evaluate_fixed_map_point(map, xhat, X, x, F, jacobian, dg_dxhat);
  }
};

// The callback for evaluations that need no ∂g/∂x̂.
struct IgnoreDgDxhat {
  template <class T>
  ROMP_HD void operator()(int, int, T) const {}
};

// The shapes with a fixed-shape kernel: the papers' network (5 hidden ELU layers of 30) at the latent
// sizes their examples use (r = 4, 6, 7: tools/rom_paper.sh). Each one adds a device compile of every
// kernel that evaluates the map, so the list stays short. Float only: the paper's map in double (33 KB)
// exceeds the 32 KB of launch parameters.
using FixedMapShapes = std::tuple<MapShape<4, 5, 30>, MapShape<6, 5, 30>, MapShape<7, 5, 30>>;

namespace map_evaluator_detail {

template <class T, class S>
FixedMapEvaluator<T, S> fixed_evaluator(const DeformationMapView<T>& map) {
  FixedMapEvaluator<T, S> evaluator;
  for (int k = 0; k < S::kParameters; ++k) evaluator.map.parameters[k] = map.host_parameters[k];
  evaluator.map.X_min = map.X_min;
  evaluator.map.X_scale = map.X_scale;
  evaluator.map.u_mean = map.u_mean;
  evaluator.map.u_std = map.u_std;
  return evaluator;
}

template <class T, class Launch, class... Shapes>
bool launch_fixed(const DeformationMapView<T>& map, Launch& launch, std::tuple<Shapes...>*) {
  const auto fits = [&map](auto shape) {
    using S = decltype(shape);
    return map.latent == S::kLatent && map.hidden_layers == S::kHiddenLayers && map.width == S::kWidth;
  };
  bool launched = false;
  ((!launched && fits(Shapes{}) ? (launch(fixed_evaluator<T, Shapes>(map)), launched = true) : false), ...);
  return launched;
}

}  // namespace map_evaluator_detail

// Calls launch(evaluator) once, with the evaluator `kernel` chooses for the map on `backend` (see
// MapKernel). The caller has checked the view's sizes against its parameter count.
template <class T, class Launch>
void with_map_evaluator(const DeformationMapView<T>& map, MapKernel kernel, Backend backend, Launch&& launch) {
  const bool fixed = kernel == MapKernel::Fixed || (kernel == MapKernel::Fastest && backend == Backend::Cuda);
  if constexpr (std::is_same_v<T, float>) {
    if (fixed && map.host_parameters &&
        map_evaluator_detail::launch_fixed(map, launch, static_cast<FixedMapShapes*>(nullptr)))
      return;
  }
  ROMP_CHECK(kernel != MapKernel::Fixed,
             "no fixed-shape map kernel for latent " + std::to_string(map.latent) + ", " +
                 std::to_string(map.hidden_layers) + " hidden layers of " + std::to_string(map.width) +
                 (std::is_same_v<T, float> ? (map.host_parameters ? "" : " (the view has no host parameters)")
                                           : " in double (float only)"));
  launch(GenericMapEvaluator<T>{map});
}

}  // namespace romp::rom
