// The differentiable substep: rest and momentum invariants, float against double, and its adjoint
// against central finite differences in double, on the test binary's backend.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/diffmpm/dense_grid.h"
#include "kernels/diffmpm/diff_step.h"
#include "tests/support/test_exec.h"

namespace romp::diffmpm {
namespace {

constexpr Index kParticles = 27;
constexpr int kCells = 10;

// Host copy of a step's inputs in planes: x, v (3 each), C, F, P (9 each), mass, volume.
template <class T>
struct HostScene {
  std::vector<T> x, v, C, F, P, mass, volume;
};

// 27 particles scattered over the middle of the unit box (their stencils reach the wall nodes of a
// 3-cell wall), moving fast enough that some nodes move toward a wall, with random C, F near I and P.
HostScene<double> random_scene(unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> position(0.2, 0.8), unit(-1.0, 1.0);
  HostScene<double> scene;
  const Index n = kParticles;
  scene.x.resize(3 * n);
  scene.v.resize(3 * n);
  scene.C.resize(9 * n);
  scene.F.resize(9 * n);
  scene.P.resize(9 * n);
  for (double& value : scene.x) value = position(random);
  for (double& value : scene.v) value = 2.0 * unit(random);
  for (double& value : scene.C) value = 5.0 * unit(random);
  for (Index p = 0; p < n; ++p)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        scene.F[(3 * r + c) * n + p] = (r == c ? 1.0 : 0.0) + 0.2 * unit(random);
        scene.P[(3 * r + c) * n + p] = 1e3 * unit(random);
      }
  const double dx = 1.0 / kCells;
  scene.mass.assign(n, 1e3 * dx * dx * dx / 8.0);
  scene.volume.assign(n, dx * dx * dx / 8.0);
  return scene;
}

template <class T>
StepParams<T> scene_params(int wall_cells, T gravity) {
  StepParams<T> params;
  params.dt = T(2e-3);
  params.dx = T(1) / T(kCells);
  params.gravity = Vec3<T>(T(0), -gravity, T(0));
  for (int a = 0; a < 3; ++a) params.domain.cells[a] = kCells;
  params.domain.wall_cells = wall_cells;
  return params;
}

// Device copies of a scene and of the step's output planes (x', v', C', F' in one buffer).
template <class T>
struct DeviceScene {
  DeviceScene(const Exec& exec, const HostScene<T>& host)
      : x(DeviceBuffer<T>::from_host(exec.backend, host.x, exec.stream)),
        v(DeviceBuffer<T>::from_host(exec.backend, host.v, exec.stream)),
        C(DeviceBuffer<T>::from_host(exec.backend, host.C, exec.stream)),
        F(DeviceBuffer<T>::from_host(exec.backend, host.F, exec.stream)),
        P(DeviceBuffer<T>::from_host(exec.backend, host.P, exec.stream)),
        mass(DeviceBuffer<T>::from_host(exec.backend, host.mass, exec.stream)),
        volume(DeviceBuffer<T>::from_host(exec.backend, host.volume, exec.stream)) {}

  ParticleInputs<T> inputs() const {
    const Index n = mass.size();
    return {n, {x.data(), n}, {v.data(), n}, {C.data(), n}, {F.data(), n}, {P.data(), n}, mass.span(), volume.span()};
  }
  DeviceBuffer<T> x, v, C, F, P, mass, volume;
};

// 24 planes (x', v', C', F') over n particles.
template <class T>
StateView<T> state_planes(T* data, Index n) {
  return {{data, n}, {data + 3 * n, n}, {data + 6 * n, n}, {data + 15 * n, n}};
}
constexpr int kStatePlanes = 24;

template <class T>
DeviceBuffer<T> grid_scratch(const Exec& exec, const StepParams<T>& params) {
  return DeviceBuffer<T>(exec.backend, kDenseGridPlanes * dense_grid_nodes(params.domain.cells));
}

// x', v', C', F' of one step, concatenated as in state_planes.
template <class T>
std::vector<T> forward(const Exec& exec, const StepParams<T>& params, const HostScene<T>& host) {
  const DeviceScene<T> scene(exec, host);
  DeviceBuffer<T> scratch = grid_scratch(exec, params);
  DeviceBuffer<T> out(exec.backend, kStatePlanes * kParticles);
  step_forward(exec, params, scene.inputs(), scratch.span(), state_planes(out.data(), kParticles));
  return out.to_host(exec.stream);
}

// ∂L/∂(x, v, C, F, P) for L = Σ weights · (x', v', C', F'), as one vector in that order.
std::vector<double> backward(const Exec& exec, const StepParams<double>& params, const HostScene<double>& host,
                             const std::vector<double>& weights) {
  const DeviceScene<double> scene(exec, host);
  DeviceBuffer<double> scratch = grid_scratch(exec, params);
  const DeviceBuffer<double> out_adjoint = DeviceBuffer<double>::from_host(exec.backend, weights, exec.stream);
  DeviceBuffer<double> in_adjoint(exec.backend, 33 * kParticles);
  double* data = in_adjoint.data();
  const Index n = kParticles;
  const StateView<double> out_view = state_planes(const_cast<double*>(out_adjoint.data()), n);
  const StateView<const double> out_planes{out_view.x, out_view.v, out_view.C, out_view.F};
  step_backward(
      exec, params, scene.inputs(), scratch.span(), out_planes,
      InputAdjoints<double>{{data, n}, {data + 3 * n, n}, {data + 6 * n, n}, {data + 15 * n, n}, {data + 24 * n, n}});
  return in_adjoint.to_host(exec.stream);
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += a[i] * b[i];
  return sum;
}

TEST(DiffStep, RestStateStaysAtRest) {
  const Exec& exec = test::exec();
  HostScene<double> scene = random_scene(1);
  std::fill(scene.v.begin(), scene.v.end(), 0.0);
  std::fill(scene.C.begin(), scene.C.end(), 0.0);
  std::fill(scene.P.begin(), scene.P.end(), 0.0);
  const std::vector<double> out = forward(exec, scene_params<double>(3, 0.0), scene);
  const Index n = kParticles;
  for (Index i = 0; i < 3 * n; ++i) EXPECT_EQ(out[i], scene.x[i]);
  for (Index i = 3 * n; i < 15 * n; ++i) EXPECT_EQ(out[i], 0.0);
  for (Index i = 0; i < 9 * n; ++i) EXPECT_EQ(out[15 * n + i], scene.F[i]);
}

// Without walls and gravity, P2G and G2P conserve linear momentum exactly (partition of unity and
// Σ w (x_i − x_p) = 0 of the quadratic B-splines), whatever the stress.
TEST(DiffStep, ConservesMomentumWithoutWallsOrGravity) {
  const HostScene<double> scene = random_scene(2);
  const std::vector<double> out = forward(test::exec(), scene_params<double>(0, 0.0), scene);
  for (int a = 0; a < 3; ++a) {
    double before = 0.0, after = 0.0, scale = 0.0;
    for (Index p = 0; p < kParticles; ++p) {
      before += scene.mass[p] * scene.v[a * kParticles + p];
      after += scene.mass[p] * out[3 * kParticles + a * kParticles + p];
      scale += scene.mass[p] * std::abs(scene.v[a * kParticles + p]);
    }
    EXPECT_NEAR(after, before, 1e-12 * scale) << "axis " << a;
  }
}

// A law gone non-finite must not make the next substep index outside the grid: NaN positions are
// clamped into the domain like any other.
TEST(DiffStep, NonFiniteStressLeavesPositionsInsideTheDomain) {
  HostScene<double> scene = random_scene(6);
  for (Index p = 0; p < kParticles; p += 3) scene.P[p] = std::nan("");
  const StepParams<double> params = scene_params<double>(3, 9.8);
  const std::vector<double> out = forward(test::exec(), params, scene);
  for (Index i = 0; i < 3 * kParticles; ++i) {
    EXPECT_GE(out[i], params.dx) << i;
    EXPECT_LE(out[i], 1.0 - params.dx) << i;
  }
}

TEST(DiffStep, FloatStepMatchesDouble) {
  const HostScene<double> scene = random_scene(3);
  auto to_float = [](const std::vector<double>& values) { return std::vector<float>(values.begin(), values.end()); };
  const HostScene<float> scene_float{to_float(scene.x), to_float(scene.v),    to_float(scene.C),     to_float(scene.F),
                                     to_float(scene.P), to_float(scene.mass), to_float(scene.volume)};
  const std::vector<double> reference = forward(test::exec(), scene_params<double>(3, 9.8), scene);
  const std::vector<float> result = forward(test::exec(), scene_params<float>(3, 9.8f), scene_float);
  double largest = 0.0;
  for (double value : reference) largest = std::max(largest, std::abs(value));
  for (std::size_t i = 0; i < reference.size(); ++i) EXPECT_NEAR(result[i], reference[i], 1e-5 * largest) << i;
}

// ∂L/∂(x, v, C, F, P) of the adjoint kernels against central differences of the forward step, for
// a random linear loss of all outputs, with walls (some nodes approach them) and gravity.
TEST(DiffStep, AdjointMatchesCentralDifferences) {
  const Exec& exec = test::exec();
  const StepParams<double> params = scene_params<double>(3, 9.8);
  const HostScene<double> scene = random_scene(4);
  std::mt19937 random(5);
  std::normal_distribution<double> normal;
  std::vector<double> weights(kStatePlanes * kParticles);
  for (double& w : weights) w = normal(random);
  const std::vector<double> gradient = backward(exec, params, scene, weights);

  struct Group {
    const char* name;
    std::vector<double> HostScene<double>::*field;
    Index offset;  // in the gradient vector
  };
  const Group groups[] = {{"x", &HostScene<double>::x, 0},
                          {"v", &HostScene<double>::v, 3 * kParticles},
                          {"C", &HostScene<double>::C, 6 * kParticles},
                          {"F", &HostScene<double>::F, 15 * kParticles},
                          {"P", &HostScene<double>::P, 24 * kParticles}};
  for (const Group& group : groups) {
    const std::vector<double>& values = scene.*group.field;
    double largest_error = 0.0, largest_gradient = 0.0;
    for (std::size_t i = 0; i < values.size(); ++i) {
      // Step ≈ ε^(1/3) of the input's scale: truncation O(h²) and rounding O(ε/h) balance near 1e-10.
      const double h = 1e-5 * std::max(1.0, std::abs(values[i]));
      HostScene<double> plus = scene, minus = scene;
      (plus.*group.field)[i] += h;
      (minus.*group.field)[i] -= h;
      const double difference =
          (dot(weights, forward(exec, params, plus)) - dot(weights, forward(exec, params, minus))) / (2.0 * h);
      largest_error = std::max(largest_error, std::abs(difference - gradient[group.offset + Index(i)]));
      largest_gradient = std::max(largest_gradient, std::abs(difference));
    }
    const double relative = largest_error / largest_gradient;
    RecordProperty(std::string("relative_error_") + group.name, std::to_string(relative));
    std::printf("d/d%s: max |adjoint - central difference| / max |gradient| = %.3g\n", group.name, relative);
    EXPECT_LE(relative, 1e-5) << "gradient with respect to " << group.name;
  }
}

}  // namespace
}  // namespace romp::diffmpm
