// The material dispatchers run through romp::for_each on the test's backend and match the host in float.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/for_each.h"
#include "kernels/material/lame.h"
#include "kernels/material/material.h"
#include "kernels/math/rotation.h"
#include "tests/support/test_exec.h"

namespace romp::material {
namespace {

using Mf = Mat3<float>;

// Relative agreement of backend and host in float: a few ulps of the SVD, log and exp, amplified by
// at most 1/(singular-value gap) in the singular vectors (the gaps below are ≥ 0.1).
constexpr float kBackendTolerance = 1e-5f;
constexpr int kDeformations = 300;
constexpr double kMinSingularValueGap = 0.1;

struct EvaluateMaterial {
  MaterialParams<float> params;
  Span<const Mf> F;
  Span<Mf> stress;
  Span<Mf> projected;
  ROMP_HD void operator()(Index i) const {
    stress[i] = first_piola(params, F[i]);
    projected[i] = project_plastic(params, F[i]);
  }
};

// Q₁ diag(σ) Q₂ with Hencky strains spread over [−0.6, 0.6] (σ in [0.55, 1.8]), enough to cross
// every yield surface below, and the singular values at least 0.1 apart.
std::vector<Mf> deformations() {
  std::mt19937_64 rng(59);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), strain(-0.6, 0.6);
  const auto rotation = [&] { return rotation_from_vector(Vec3<double>(angle(rng), angle(rng), angle(rng))); };
  std::vector<Mf> result;
  while (int(result.size()) < kDeformations) {
    const Vec3<double> sigma(std::exp(strain(rng)), std::exp(strain(rng)), std::exp(strain(rng)));
    const double gap =
        std::min({std::abs(sigma[0] - sigma[1]), std::abs(sigma[1] - sigma[2]), std::abs(sigma[0] - sigma[2])});
    if (gap < kMinSingularValueGap) continue;
    const Mat3<double> F = rotation() * Mat3<double>::diag(sigma) * rotation();
    Mf F_float;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) F_float(r, c) = float(F(r, c));
    result.push_back(F_float);
  }
  return result;
}

std::vector<MaterialParams<float>> every_material() {
  const Lame<float> jelly = lame_from_young_poisson(1e5f, 0.2f);
  const Lame<float> sand = lame_from_young_poisson(1e6f, 0.2f);
  const Lame<float> plasticine = lame_from_young_poisson(3e5f, 0.25f);
  const Lame<float> water = lame_from_young_poisson(1e5f, 0.3f);
  return {MaterialParams<float>::fixed_corotated(jelly),
          MaterialParams<float>::neo_hookean(jelly),
          MaterialParams<float>::hencky_stvk(sand),
          MaterialParams<float>::drucker_prager(sand, 25.0f, 0.0f),
          MaterialParams<float>::von_mises(plasticine, 5e3f),
          MaterialParams<float>::weakly_compressible_fluid(water.lambda)};
}

float relative_difference(const Mf& actual, const Mf& expected) {
  return frobenius_norm(actual - expected) / frobenius_norm(expected);
}

TEST(MaterialDispatch, BackendMatchesHostEvaluationForEveryModel) {
  const Exec& exec = test::exec();
  const std::vector<Mf> host_F = deformations();
  const DeviceBuffer<Mf> F = DeviceBuffer<Mf>::from_host(exec.backend, host_F, exec.stream);
  DeviceBuffer<Mf> stress(exec.backend, kDeformations), projected(exec.backend, kDeformations);
  for (const MaterialParams<float>& params : every_material()) {
    SCOPED_TRACE("material model " + std::to_string(int(params.model)));
    for_each(exec, kDeformations, EvaluateMaterial{params, F.span(), stress.span(), projected.span()});
    const std::vector<Mf> backend_stress = stress.to_host(exec.stream);
    const std::vector<Mf> backend_projected = projected.to_host(exec.stream);
    for (int i = 0; i < kDeformations; ++i) {
      EXPECT_LE(relative_difference(backend_stress[i], first_piola(params, host_F[i])), kBackendTolerance) << i;
      EXPECT_LE(relative_difference(backend_projected[i], project_plastic(params, host_F[i])), kBackendTolerance) << i;
    }
  }
}

}  // namespace
}  // namespace romp::material
