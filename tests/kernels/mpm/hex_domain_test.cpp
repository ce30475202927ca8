// Particle-domain weights: exact values on a lattice cube, and the reproduction identities on general hexahedra.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels/mpm/hex_domain.h"
#include "kernels/mpm/particle_domains.h"

namespace romp::mpm {
namespace {

using Vec = Vec3<double>;
constexpr double kTolerance = 1e-12;

HexDomainWeights<double> weights_of(const Vec (&corners)[kDomainCorners]) { return hex_domain_weights(corners); }

TEST(HexDomain, LatticeCubeHasEqualWeightsAndFaceGradients) {
  const double h = 0.25;
  Vec corners[kDomainCorners];
  for (int c = 0; c < kDomainCorners; ++c)
    corners[c] = Vec(1, 2, 3) + (0.5 * h) * corner_reference_coordinates<double>(c);
  const HexDomainWeights<double> w = weights_of(corners);
  EXPECT_NEAR(w.volume, h * h * h, kTolerance);
  for (int c = 0; c < kDomainCorners; ++c) {
    EXPECT_NEAR(w.weight[c], 0.125, kTolerance);
    // (1/V) ∫ ∂N/∂X over a cube of side h: ±1/(4h) on every axis.
    const Vec expected = (1.0 / (4.0 * h)) * corner_reference_coordinates<double>(c);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(w.gradient[c][a], expected[a], kTolerance) << c << " " << a;
  }
}

// For any valid hexahedron: Σ ω = 1, Σ g = 0 (constants are reproduced), Σ X gᵀ = I (linear fields
// have the right gradient).
TEST(HexDomain, GeneralHexahedraReproduceConstantAndLinearFields) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  for (int trial = 0; trial < 20; ++trial) {
    Vec corners[kDomainCorners];
    for (int c = 0; c < kDomainCorners; ++c)
      corners[c] = corner_reference_coordinates<double>(c) + Vec(jitter(rng), jitter(rng), jitter(rng));
    const HexDomainWeights<double> w = weights_of(corners);
    double weight_sum = 0.0;
    Vec gradient_sum = Vec::zero();
    Mat3<double> linear = Mat3<double>::zero();
    for (int c = 0; c < kDomainCorners; ++c) {
      weight_sum += w.weight[c];
      gradient_sum += w.gradient[c];
      linear += Mat3<double>::outer(corners[c], w.gradient[c]);
    }
    EXPECT_NEAR(weight_sum, 1.0, kTolerance);
    EXPECT_LT(norm(gradient_sum), kTolerance);
    EXPECT_LT(frobenius_norm(linear - Mat3<double>::identity()), 1e-11);
    EXPECT_GT(w.volume, 0.0);
  }
}

// K = 3 / (‖F‖_F ‖F⁻¹‖_F) from the stretches: 1 without distortion, the paper's 0.6 passed by a
// four-fold stretch, finite for flat and inverted F through the clamp.
TEST(DeformationQuality, OneForRotationsAndFallingWithDistortion) {
  EXPECT_DOUBLE_EQ(deformation_quality(Vec(1, 1, 1), 0.1), 1.0);
  EXPECT_DOUBLE_EQ(deformation_quality(Vec(2, 2, 2), 0.1), 1.0);
  EXPECT_NEAR(deformation_quality(Vec(2, 1, 1), 0.1), 3.0 / std::sqrt(6.0 * 2.25), kTolerance);
  EXPECT_GT(deformation_quality(Vec(2, 1, 1), 0.1), 0.6);
  EXPECT_LT(deformation_quality(Vec(4, 1, 1), 0.1), 0.6);
  EXPECT_NEAR(deformation_quality(Vec(1, 1, -0.5), 0.1), deformation_quality(Vec(1, 1, 0.1), 0.1), kTolerance);
}

}  // namespace
}  // namespace romp::mpm
