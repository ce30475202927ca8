// The fused deformation-map kernels: one forward sweep keeping the ELU slopes, then three reverse sweeps
// for the rows of the Jacobian (see deformation_map_eval.h), with the generic or a fixed-shape evaluator.
#include "kernels/rom/deformation_map_eval.h"

#include <string>
#include <type_traits>

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/rom/map_evaluators.h"

namespace romp::rom {
namespace {

template <class T, class Map>
struct MapPoint {
  Map map;
  const T* xhat;
  Vec3Planes<const T> X;
  DeformationMapOutputs<T> out;

  ROMP_HD void operator()(Index i) const {
    Vec3<T> x;
    Mat3<T> F = Mat3<T>::identity();
    T* const dg = out.dg_dxhat.data();
    const Index n = X.count();
    const int r = map.latent();
    map(xhat, X.load(i), x, F, out.F.data() || dg, [dg, n, r, i](int o, int j, T value) {
      if (dg) dg[(o * r + j) * n + i] = value;
    });
    if (out.x.data()) out.x.store(i, x);
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
                              Vec3Planes<const T> X, const DeformationMapOutputs<T>& out, MapKernel kernel,
                              Span<const std::int64_t> live) {
  ROMP_CHECK(map.latent >= 1 && map.latent <= kMaxMapLatent, "the fused map evaluator takes a latent size r in [1, " +
                                                                 std::to_string(kMaxMapLatent) + "], got " +
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
  with_map_evaluator(map, kernel, exec.backend, [&](const auto& evaluator) {
    for_each_bounded(exec, n, live, MapPoint<T, std::decay_t<decltype(evaluator)>>{evaluator, xhat.data(), X, out});
  });
}

template void evaluate_deformation_map<float>(const Exec&, const DeformationMapView<float>&, Span<const float>,
                                              Vec3Planes<const float>, const DeformationMapOutputs<float>&, MapKernel,
                                              Span<const std::int64_t>);
template void evaluate_deformation_map<double>(const Exec&, const DeformationMapView<double>&, Span<const double>,
                                               Vec3Planes<const double>, const DeformationMapOutputs<double>&,
                                               MapKernel, Span<const std::int64_t>);

}  // namespace romp::rom
