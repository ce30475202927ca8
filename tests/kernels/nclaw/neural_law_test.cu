// The fused law kernels on the test binary's backend: exact rest state, the particle selection, agreement
// with the per-particle law evaluated on the host (the CPU twin), in-place plasticity, and weight
// gradients that are the sums of the particles' own.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/nclaw/neural_law.h"
#include "tests/support/test_exec.h"

namespace romp::nclaw {
namespace {

constexpr Index kParticles = 96;

// Random weights (3× Xavier scale, so that the GELUs work off their linear part) on the host and the device.
struct Weights {
  std::vector<float> host;
  DeviceBuffer<float> device;

  explicit Weights(unsigned seed) : host(kLawWeights), device(test::exec().backend, kLawWeights) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    for (Index i = 0; i < kLawWeights; ++i) {
      const int inputs = i < kLawWidth * kLawInputs ? kLawInputs : kLawWidth;
      const int outputs = i < kLawWidth * (kLawInputs + kLawWidth) ? kLawWidth : kLawOutputs;
      host[i] = 3.0f * std::sqrt(6.0f / float(inputs + outputs)) * unit(random);
    }
    upload(test::exec().backend, device.span(), Span<const float>(host.data(), kLawWeights));
  }
  static LawWeights<float> view(const float* base) {
    return {base, base + kLawWidth * kLawInputs, base + kLawWidth * (kLawInputs + kLawWidth)};
  }
  LawWeights<float> on_host() const { return view(host.data()); }
  LawWeights<float> on_device() const { return view(device.data()); }
};

// n matrices near I, a quarter of them inverted, as planes.
std::vector<float> deformations(Index n, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<float> normal(0.0f, 0.3f);
  std::vector<float> F(9 * n);
  for (Index p = 0; p < n; ++p)
    for (int e = 0; e < 9; ++e)
      F[e * n + p] = (e % 4 == 0 ? 1.0f : 0.0f) * (p % 4 == 0 && e >= 6 ? -1.0f : 1.0f) + normal(random);
  return F;
}

DeviceBuffer<float> on_device(const std::vector<float>& host) {
  DeviceBuffer<float> buffer(test::exec().backend, Index(host.size()));
  upload(test::exec().backend, buffer.span(), Span<const float>(host.data(), Index(host.size())));
  return buffer;
}

std::vector<float> on_host(const DeviceBuffer<float>& buffer) {
  return download(test::exec().backend, Span<const float>(buffer.data(), buffer.size()), test::exec().stream);
}

Mat3<float> matrix(const std::vector<float>& planes, Index n, Index p) {
  return Mat3Planes<const float>(planes.data(), n).load(p);
}

TEST(NeuralLaw, RestStateIsExactlyStressFreeAndPlasticityFree) {
  const Exec& exec = test::exec();
  const Weights weights(1);
  std::vector<float> identity(9 * kParticles, 0.0f);
  for (Index p = 0; p < kParticles; ++p)
    identity[0 * kParticles + p] = identity[4 * kParticles + p] = identity[8 * kParticles + p] = 1.0f;
  const DeviceBuffer<float> F = on_device(identity);
  DeviceBuffer<float> Y(exec.backend, 9 * kParticles);
  law_forward<float>(exec, weights.on_device(), {1.0f, false}, {F.data(), kParticles}, {Y.data(), kParticles});
  EXPECT_EQ(on_host(Y), std::vector<float>(9 * kParticles, 0.0f));
  law_forward<float>(exec, weights.on_device(), {1e-3f, true}, {F.data(), kParticles}, {Y.data(), kParticles});
  EXPECT_EQ(on_host(Y), identity);
}

TEST(NeuralLaw, MatchesTheLawEvaluatedOnTheHost) {
  const Exec& exec = test::exec();
  const Weights weights(2);
  const std::vector<float> host_F = deformations(kParticles, 3);
  const DeviceBuffer<float> F = on_device(host_F);
  DeviceBuffer<float> Y(exec.backend, 9 * kParticles);
  law_forward<float>(exec, weights.on_device(), {1.0f, false}, {F.data(), kParticles}, {Y.data(), kParticles});
  const std::vector<float> result = on_host(Y);
  for (Index p = 0; p < kParticles; ++p) {
    const Mat3<float> expected = evaluate_law(weights.on_host(), {1.0f, false}, matrix(host_F, kParticles, p));
    const Mat3<float> got = matrix(result, kParticles, p);
    EXPECT_LE(max_abs(got - expected), 1e-5f * std::max(1.0f, max_abs(expected))) << "particle " << p;
  }
}

// The backward pass against law_backward of one particle evaluated on the host (on the CPU backend: the
// block path of law_lanes.h against the per-particle one the device runs; on CUDA: the device against it).
TEST(NeuralLaw, BackwardMatchesTheParticleLawOnTheHost) {
  const Exec& exec = test::exec();
  const Weights weights(9);
  const Index n = 37;  // two full blocks of 16 and a partial one
  const std::vector<float> host_F = deformations(n, 10);
  std::vector<float> host_dY(9 * n);
  std::mt19937 random(11);
  std::normal_distribution<float> normal;
  for (float& value : host_dY) value = normal(random);
  const DeviceBuffer<float> F = on_device(host_F), dY = on_device(host_dY);
  DeviceBuffer<float> dF(exec.backend, 9 * n), dW(exec.backend, kLawWeights),
      activations(exec.backend, kLawActivationPlanes * n);
  const LawWeights<float> dW_view = Weights::view(dW.data());
  const LawOutput<float> plastic{1e-3f, true};
  law_backward<float>(exec, weights.on_device(), plastic, {F.data(), n}, {dY.data(), n}, activations.span(),
                      {{dF.data(), n},
                       const_cast<float*>(dW_view.input),
                       const_cast<float*>(dW_view.hidden),
                       const_cast<float*>(dW_view.output)});
  const std::vector<float> result_dF = on_host(dF), result_rows = on_host(activations);

  std::vector<float> expected_rows(kLawActivationPlanes * n);
  for (Index p = 0; p < n; ++p) {
    const Mat3<float> expected = law_backward(weights.on_host(), plastic, matrix(host_F, n, p), matrix(host_dY, n, p),
                                              activation_rows(expected_rows.data(), n, p));
    EXPECT_LE(max_abs(matrix(result_dF, n, p) - expected), 1e-5f * std::max(1.0f, max_abs(expected)))
        << "particle " << p;
  }
  for (Index i = 0; i < kLawActivationPlanes * n; ++i)
    EXPECT_NEAR(result_rows[i], expected_rows[i], 1e-5f * std::max(1.0f, std::abs(expected_rows[i])))
        << "plane " << i / n << ", particle " << i % n;
}

// Particles of material 1 outside Dirichlet groups take the plastic law in place; the others keep F.
TEST(NeuralLaw, ProjectsOnlyTheSelectedParticlesInPlace) {
  const Exec& exec = test::exec();
  const Weights weights(4);
  const std::vector<float> host_F = deformations(kParticles, 5);
  std::vector<std::int32_t> material(kParticles), group(kParticles);
  for (Index p = 0; p < kParticles; ++p) {
    material[p] = std::int32_t(p % 3);
    group[p] = p % 5 == 0 ? 0 : mpm::kNoDirichletGroup;
  }
  DeviceBuffer<std::int32_t> material_d(exec.backend, kParticles), group_d(exec.backend, kParticles);
  upload(exec.backend, material_d.span(), Span<const std::int32_t>(material.data(), kParticles));
  upload(exec.backend, group_d.span(), Span<const std::int32_t>(group.data(), kParticles));
  DeviceBuffer<float> F = on_device(host_F);
  law_forward<float>(exec, weights.on_device(), {1e-3f, true}, {F.data(), kParticles}, {F.data(), kParticles},
                     {material_d.data(), 1, group_d.data()});
  const std::vector<float> result = on_host(F);
  int projected = 0;
  for (Index p = 0; p < kParticles; ++p) {
    const Mat3<float> before = matrix(host_F, kParticles, p), after = matrix(result, kParticles, p);
    if (material[p] == 1 && group[p] == mpm::kNoDirichletGroup) {
      const Mat3<float> expected = evaluate_law(weights.on_host(), {1e-3f, true}, before);
      EXPECT_LE(max_abs(after - expected), 1e-6f * max_abs(expected)) << "particle " << p;
      EXPECT_FALSE(after == before) << "particle " << p;
      ++projected;
    } else {
      EXPECT_EQ(after, before) << "particle " << p;
    }
  }
  EXPECT_EQ(projected, 26);
}

// The weight gradients of a batch are the sums of the gradients of its particles alone, and dF does not
// depend on the batch.
TEST(NeuralLaw, WeightGradientsAreTheSumsOverParticles) {
  const Exec& exec = test::exec();
  const Weights weights(6);
  const Index n = 12;
  const std::vector<float> host_F = deformations(n, 7);
  std::vector<float> host_dY(9 * n);
  std::mt19937 random(8);
  std::normal_distribution<float> normal;
  for (float& value : host_dY) value = normal(random);

  const auto backward = [&](const std::vector<float>& F_planes, const std::vector<float>& dY_planes, Index count) {
    const DeviceBuffer<float> F = on_device(F_planes), dY = on_device(dY_planes);
    DeviceBuffer<float> dF(exec.backend, 9 * count), dW(exec.backend, kLawWeights),
        activations(exec.backend, kLawActivationPlanes * count);
    const LawWeights<float> dW_view = Weights::view(dW.data());
    law_backward<float>(exec, weights.on_device(), {1e-3f, true}, {F.data(), count}, {dY.data(), count},
                        activations.span(),
                        {{dF.data(), count},
                         const_cast<float*>(dW_view.input),
                         const_cast<float*>(dW_view.hidden),
                         const_cast<float*>(dW_view.output)});
    return std::pair{on_host(dF), on_host(dW)};
  };
  const auto [batch_dF, batch_dW] = backward(host_F, host_dY, n);
  std::vector<double> summed(kLawWeights, 0.0);
  for (Index p = 0; p < n; ++p) {
    std::vector<float> F_p(9), dY_p(9);
    for (int e = 0; e < 9; ++e) {
      F_p[e] = host_F[e * n + p];
      dY_p[e] = host_dY[e * n + p];
    }
    const auto [dF_p, dW_p] = backward(F_p, dY_p, 1);
    for (int e = 0; e < 9; ++e) EXPECT_FLOAT_EQ(batch_dF[e * n + p], dF_p[e]) << "particle " << p << ", entry " << e;
    for (Index i = 0; i < kLawWeights; ++i) summed[i] += dW_p[i];
  }
  double largest = 0.0;
  for (double value : summed) largest = std::max(largest, std::abs(value));
  for (Index i = 0; i < kLawWeights; ++i) EXPECT_NEAR(batch_dW[i], summed[i], 1e-5 * largest) << "weight " << i;
}

}  // namespace
}  // namespace romp::nclaw
