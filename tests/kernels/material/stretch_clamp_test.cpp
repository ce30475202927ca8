// Inversion handling: principal stretches below the floor are raised to it before any stress is evaluated.
#include <gtest/gtest.h>

#include <random>

#include "kernels/material/lame.h"
#include "kernels/material/material.h"
#include "kernels/material/stretch_clamp.h"
#include "kernels/math/finite.h"
#include "kernels/math/rotation.h"
#include "kernels/svd/svd3.h"

namespace romp::material {
namespace {

using M = Mat3<double>;
using Vec = Vec3<double>;

constexpr double kFloor = 0.1;
constexpr double kTolerance = 1e-12;  // relative, double precision reconstructions
const Lame<double> kLame = lame_from_young_poisson(1e6, 0.3);

M random_rotation(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  return rotation_from_vector(Vec(angle(rng), angle(rng), angle(rng)));
}

// R₁ diag(σ) R₂ᵀ: a deformation with prescribed signed singular values.
M with_stretches(std::mt19937_64& rng, const Vec& sigma) {
  return random_rotation(rng) * times_transpose(M::diag(sigma), random_rotation(rng));
}

std::vector<MaterialParams<double>> hyperelastic_models() {
  using P = MaterialParams<double>;
  return {P::fixed_corotated(kLame), P::neo_hookean(kLame), P::hencky_stvk(kLame)};
}

double relative_difference(const M& a, const M& b) { return frobenius_norm(a - b) / std::max(frobenius_norm(b), 1.0); }

TEST(StretchClamp, LeavesAValidDeformationBitForBit) {
  std::mt19937_64 rng(7);
  for (const Vec& sigma : {Vec(1, 1, 1), Vec(2, 1, 0.5), Vec(3, 0.4, 0.12), Vec(1.0, 0.9, 0.101)}) {
    const M F = with_stretches(rng, sigma);
    const M clamped = clamp_stretches(F, kFloor);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(clamped(r, c), F(r, c)) << "sigma " << sigma[2];
  }
}

TEST(StretchClamp, RaisesSmallAndNegativeStretchesKeepingTheFrames) {
  std::mt19937_64 rng(11);
  for (const Vec& sigma : {Vec(1, 1, 0.05), Vec(1.5, 1, -0.5), Vec(1, 0.02, -0.01), Vec(2, 1e-9, 0), Vec(0, 0, 0)}) {
    const M F = with_stretches(rng, sigma);
    const M clamped = clamp_stretches(F, kFloor);
    const Svd3<double> before = svd3(F), after = svd3(clamped);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(after.sigma[i], std::max(before.sigma[i], kFloor), 1e-12) << i;
    // The same rotations: U diag(σ̃) Vᵀ rebuilt from F's own SVD equals the clamped F.
    Vec expected = before.sigma;
    for (int i = 0; i < 3; ++i) expected[i] = std::max(expected[i], kFloor);
    EXPECT_LT(relative_difference(clamped, from_principal(before.U, expected, before.V)), kTolerance);
    EXPECT_GT(determinant(clamped), 0.0);
  }
}

TEST(StretchClamp, EveryHyperelasticStressIsTheStressOfTheClampedDeformation) {
  std::mt19937_64 rng(13);
  for (const MaterialParams<double>& exact : hyperelastic_models()) {
    const MaterialParams<double> clamped = exact.with_min_stretch(kFloor);
    for (const Vec& sigma : {Vec(1.2, 1, -0.3), Vec(1, 0.5, 0.01), Vec(1, 1, -2)}) {
      const M F = with_stretches(rng, sigma);
      const M F_valid = clamp_stretches(F, kFloor);
      const M P = first_piola(clamped, F);
      ASSERT_TRUE(is_finite(P));
      EXPECT_LT(relative_difference(P, first_piola(exact, F_valid)), kTolerance);
      EXPECT_DOUBLE_EQ(energy_density(clamped, F), energy_density(exact, F_valid));
      const M dF = with_stretches(rng, Vec(0.3, 0.2, 0.1));
      EXPECT_LT(
          relative_difference(first_piola_differential(clamped, F, dF), first_piola_differential(exact, F_valid, dF)),
          kTolerance);
    }
  }
}

// A flat or inverted element feels the stress of one compressed to the floor: it pushes the volume
// back up (the stress's power on the un-inverting direction is negative: energy decreases).
TEST(StretchClamp, FlatAndInvertedElementsArePushedBackToPositiveVolume) {
  for (const MaterialParams<double>& exact : hyperelastic_models()) {
    const MaterialParams<double> clamped = exact.with_min_stretch(kFloor);
    for (double s : {0.0, 1e-6, -0.2, -1.0}) {
      const M F = M::diag(Vec(1, 1, s));
      const M P = first_piola(clamped, F);
      ASSERT_TRUE(is_finite(P)) << s;
      // Increasing the third stretch must lower the energy: P : e₃e₃ᵀ < 0.
      EXPECT_LT(P(2, 2), 0.0) << "model " << int(exact.model) << ", stretch " << s;
    }
  }
}

TEST(StretchClamp, FloatStressOfADegenerateDeformationIsFinite) {
  const MaterialParams<float> params =
      MaterialParams<float>::fixed_corotated(lame_from_young_poisson(1e6f, 0.45f)).with_min_stretch(0.1f);
  for (const Mat3<float>& F : {Mat3<float>::zero(), Mat3<float>::diag(Vec3<float>(1e-20f, 1.0f, -1e3f)),
                               Mat3<float>::diag(Vec3<float>(-1.0f, -1.0f, -1.0f))})
    EXPECT_TRUE(is_finite(first_piola(params, F)));
}

}  // namespace
}  // namespace romp::material
