// A deformation map g(X; x̂) as plain Eigen matrices in double, with the fused evaluator's normalisation and
// packing: the independent reference of the ROM kernels' tests.
#pragma once

#include <Eigen/Dense>

#include <cmath>
#include <random>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/math/vec3.h"
#include "kernels/rom/deformation_map_eval.h"

namespace romp::rom {

// A map as plain Eigen matrices, with the evaluator's normalisation.
struct ReferenceMap {
  int latent = 0;
  std::vector<Eigen::MatrixXd> weights;
  std::vector<Eigen::VectorXd> biases;
  Eigen::Vector3d X_min, X_scale, u_mean, u_std;

  Eigen::Vector3d g(const Eigen::VectorXd& xhat, const Eigen::Vector3d& X) const {
    Eigen::VectorXd a(latent + 3);
    a << xhat, (X - X_min).cwiseProduct(X_scale);
    for (std::size_t k = 0; k < weights.size(); ++k) {
      a = weights[k] * a + biases[k];
      if (k + 1 < weights.size()) a = a.unaryExpr([](double z) { return z > 0.0 ? z : std::expm1(z); });
    }
    return X + u_mean + u_std.cwiseProduct(a);
  }

  // The packed buffer of deformation_map_eval.h: per layer, weight (row-major) then bias.
  std::vector<double> packed() const {
    std::vector<double> values;
    for (std::size_t k = 0; k < weights.size(); ++k) {
      for (int r = 0; r < weights[k].rows(); ++r)
        for (int c = 0; c < weights[k].cols(); ++c) values.push_back(weights[k](r, c));
      for (int r = 0; r < biases[k].size(); ++r) values.push_back(biases[k](r));
    }
    return values;
  }
};

// Xavier-like random weights with biases, so hidden units sit on both sides of ELU's kink.
inline ReferenceMap random_map(int latent, int hidden_layers, int width, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  ReferenceMap map;
  map.latent = latent;
  for (int k = 0; k <= hidden_layers; ++k) {
    const int in = k == 0 ? latent + 3 : width, out = k == hidden_layers ? 3 : width;
    const double bound = std::sqrt(6.0 / (in + out));
    map.weights.push_back(Eigen::MatrixXd::NullaryExpr(out, in, [&] { return bound * unit(random); }));
    map.biases.push_back(Eigen::VectorXd::NullaryExpr(out, [&] { return 0.5 * unit(random); }));
  }
  map.X_min = Eigen::Vector3d(-0.1, 0.2, 0.05);
  map.X_scale = Eigen::Vector3d(1.0 / 0.3, 1.0 / 0.4, 1.0 / 0.2);
  map.u_mean = Eigen::Vector3d(0.01, -0.02, 0.005);
  map.u_std = Eigen::Vector3d(0.03, 0.05, 0.02);
  return map;
}

template <class T>
Vec3<T> vec3(const Eigen::Vector3d& v) {
  return Vec3<T>(T(v(0)), T(v(1)), T(v(2)));
}

// A reference map's parameters in T on exec's backend and on the host (as map_view gives them, so
// that the fixed-shape kernels run for their sizes), and the evaluator's view of them.
template <class T>
struct UploadedMap {
  std::vector<T> host;
  DeviceBuffer<T> parameters;
  DeformationMapView<T> view;
};

template <class T>
UploadedMap<T> upload(const Exec& exec, const ReferenceMap& reference, int hidden_layers, int width) {
  std::vector<T> packed;
  for (double v : reference.packed()) packed.push_back(T(v));
  UploadedMap<T> uploaded{packed, DeviceBuffer<T>::from_host(exec.backend, packed, exec.stream), {}};
  DeformationMapView<T>& map = uploaded.view;
  map.host_parameters = uploaded.host.data();
  map.latent = reference.latent;
  map.hidden_layers = hidden_layers;
  map.width = width;
  map.parameters = Span<const T>(uploaded.parameters.data(), uploaded.parameters.size());
  map.X_min = vec3<T>(reference.X_min);
  map.X_scale = vec3<T>(reference.X_scale);
  map.u_mean = vec3<T>(reference.u_mean);
  map.u_std = vec3<T>(reference.u_std);
  return uploaded;
}

}  // namespace romp::rom
