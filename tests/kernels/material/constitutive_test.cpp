// Constitutive models in double precision: energies, stresses, differentials and return maps against their definitions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "kernels/material/drucker_prager.h"
#include "kernels/material/fixed_corotated.h"
#include "kernels/material/hencky.h"
#include "kernels/material/isotropic.h"
#include "kernels/material/lame.h"
#include "kernels/material/material.h"
#include "kernels/material/neo_hookean.h"
#include "kernels/material/volume.h"
#include "kernels/material/von_mises.h"
#include "kernels/material/weakly_compressible_fluid.h"
#include "kernels/math/finite.h"
#include "kernels/math/rotation.h"

namespace romp::material {
namespace {

using M = Mat3<double>;
using Vec = Vec3<double>;

// Tolerances stated by the specification of the models.
constexpr double kFiniteDifferenceTolerance = 1e-6;  // relative, central differences
constexpr double kInvarianceTolerance = 1e-10;       // relative, rotations and isotropy
constexpr double kYieldSurfaceTolerance = 1e-9;      // absolute, in log strain
// Central-difference step: truncation (h² ψ''') and rounding (ε ψ / h) errors both stay near 1e-10.
constexpr double kFiniteDifferenceStep = 1e-6;
constexpr int kSamples = 40;
constexpr double kPi = 3.14159265358979323846;

// The paper's materials (Ma et al. 2023, App. B): jelly, sand, plasticine.
const Lame<double> kJelly = lame_from_young_poisson(1e5, 0.2);
const Lame<double> kSand = lame_from_young_poisson(1e6, 0.2);
constexpr double kSandFrictionAngleDegrees = 25.0;
const Lame<double> kPlasticine = lame_from_young_poisson(3e5, 0.25);
constexpr double kPlasticineYieldStress = 5e3;

double uniform(std::mt19937_64& rng, double low, double high) {
  return std::uniform_real_distribution<double>(low, high)(rng);
}

M random_rotation(std::mt19937_64& rng) {
  return rotation_from_vector(Vec(uniform(rng, -3, 3), uniform(rng, -3, 3), uniform(rng, -3, 3)));
}

M random_matrix(std::mt19937_64& rng, double amplitude) {
  M A;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) A(r, c) = uniform(rng, -amplitude, amplitude);
  return A;
}

M near_identity(std::mt19937_64& rng) { return M::identity() + random_matrix(rng, 0.1); }

// Q₁ diag(σ) Q₂ with σ uniform in [0.3, 3].
M large_deformation(std::mt19937_64& rng) {
  const Vec sigma(uniform(rng, 0.3, 3), uniform(rng, 0.3, 3), uniform(rng, 0.3, 3));
  return random_rotation(rng) * M::diag(sigma) * random_rotation(rng);
}

// Q₁ diag(σ) Q₂ with singular values at least 0.2 apart.
M separated_deformation(std::mt19937_64& rng) {
  const double smallest = uniform(rng, 0.4, 1.0);
  const double middle = smallest + uniform(rng, 0.2, 0.8);
  const double largest = middle + uniform(rng, 0.2, 0.8);
  return random_rotation(rng) * M::diag(largest, smallest, middle) * random_rotation(rng);
}

M unit(int r, int c) {
  M E = M::zero();
  E(r, c) = 1.0;
  return E;
}

double relative_error(const M& actual, const M& expected) {
  return frobenius_norm(actual - expected) / frobenius_norm(expected);
}

// ∂ψ/∂F entry by entry, by central differences.
template <class Model>
M energy_gradient_by_differences(const Model& model, const M& F) {
  M gradient;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const M step = kFiniteDifferenceStep * unit(r, c);
      gradient(r, c) = (model.energy_density(F + step) - model.energy_density(F - step)) / (2 * kFiniteDifferenceStep);
    }
  return gradient;
}

// (∂P/∂F : dF) by central differences along dF.
template <class Model>
M stress_derivative_by_differences(const Model& model, const M& F, const M& dF) {
  const M step = kFiniteDifferenceStep * dF;
  return (model.first_piola(F + step) - model.first_piola(F - step)) * (1 / (2 * kFiniteDifferenceStep));
}

// ---------------------------------------------------------------------------------------------------
// Properties every model shares, run over all six.

template <class Model>
struct TestModel;
template <>
struct TestModel<FixedCorotated<double>> {
  static constexpr const char* kName = "FixedCorotated";
  static FixedCorotated<double> make() { return {kJelly.mu, kJelly.lambda}; }
};
template <>
struct TestModel<NeoHookean<double>> {
  static constexpr const char* kName = "NeoHookean";
  static NeoHookean<double> make() { return {kJelly.mu, kJelly.lambda}; }
};
template <>
struct TestModel<HenckyStVK<double>> {
  static constexpr const char* kName = "HenckyStVK";
  static HenckyStVK<double> make() { return {kSand.mu, kSand.lambda}; }
};
template <>
struct TestModel<DruckerPrager<double>> {
  static constexpr const char* kName = "DruckerPrager";
  static DruckerPrager<double> make() {
    return {{kSand.mu, kSand.lambda}, drucker_prager_alpha(kSandFrictionAngleDegrees), 0.0};
  }
};
template <>
struct TestModel<VonMises<double>> {
  static constexpr const char* kName = "VonMises";
  static VonMises<double> make() { return {{kPlasticine.mu, kPlasticine.lambda}, kPlasticineYieldStress}; }
};
template <>
struct TestModel<WeaklyCompressibleFluid<double>> {
  static constexpr const char* kName = "WeaklyCompressibleFluid";
  static WeaklyCompressibleFluid<double> make() { return {lame_from_young_poisson(1e5, 0.3).lambda}; }
};

struct ModelName {
  template <class Model>
  static std::string GetName(int) {
    return TestModel<Model>::kName;
  }
};

template <class Model>
class ConstitutiveModel : public testing::Test {
 protected:
  const Model model = TestModel<Model>::make();
  std::mt19937_64 rng{20240611};
};

using AllModels = testing::Types<FixedCorotated<double>, NeoHookean<double>, HenckyStVK<double>, DruckerPrager<double>,
                                 VonMises<double>, WeaklyCompressibleFluid<double>>;
TYPED_TEST_SUITE(ConstitutiveModel, AllModels, ModelName);

TYPED_TEST(ConstitutiveModel, StressAndEnergyVanishAtRest) {
  const M I = M::identity();
  EXPECT_NEAR(this->model.energy_density(I), 0.0, 1e-12);
  EXPECT_LE(max_abs(this->model.first_piola(I)), 1e-9);  // of moduli 1e4..1e6 Pa
}

TYPED_TEST(ConstitutiveModel, StressIsTheEnergyGradientNearRest) {
  for (int sample = 0; sample < kSamples; ++sample) {
    const M F = near_identity(this->rng);
    EXPECT_LE(relative_error(energy_gradient_by_differences(this->model, F), this->model.first_piola(F)),
              kFiniteDifferenceTolerance)
        << "sample " << sample;
  }
}

TYPED_TEST(ConstitutiveModel, StressIsTheEnergyGradientUnderLargeDeformation) {
  for (int sample = 0; sample < kSamples; ++sample) {
    const M F = large_deformation(this->rng);
    EXPECT_LE(relative_error(energy_gradient_by_differences(this->model, F), this->model.first_piola(F)),
              kFiniteDifferenceTolerance)
        << "sample " << sample;
  }
}

TYPED_TEST(ConstitutiveModel, DifferentialIsTheStressDerivative) {
  for (int sample = 0; sample < kSamples; ++sample) {
    const M F = separated_deformation(this->rng);
    const M dF = random_matrix(this->rng, 1.0);
    EXPECT_LE(relative_error(this->model.first_piola_differential(F, dF),
                             stress_derivative_by_differences(this->model, F, dF)),
              kFiniteDifferenceTolerance)
        << "sample " << sample;
  }
}

TYPED_TEST(ConstitutiveModel, DifferentialIsTheStressDerivativeAtRepeatedStretches) {
  const M Q = random_rotation(this->rng);
  for (const M& F : {M::identity(), M::diag(2, 2, 1), Q * M::diag(2, 2, 1) * transpose(Q), M::diag(0.5, 0.5, 0.5)}) {
    for (int sample = 0; sample < kSamples / 4; ++sample) {
      const M dF = random_matrix(this->rng, 1.0);
      const M dP = this->model.first_piola_differential(F, dF);
      ASSERT_TRUE(is_finite(dP));
      EXPECT_LE(relative_error(dP, stress_derivative_by_differences(this->model, F, dF)), kFiniteDifferenceTolerance)
          << "F diagonal " << F(0, 0) << ", " << F(1, 1) << ", " << F(2, 2) << ", sample " << sample;
    }
  }
}

TYPED_TEST(ConstitutiveModel, DifferentialIsSymmetric) {
  // δP₁ : δF₂ = δP₂ : δF₁: the differential is the action of the (symmetric) energy Hessian.
  for (int sample = 0; sample < kSamples; ++sample) {
    const M F = large_deformation(this->rng);
    const M dF1 = random_matrix(this->rng, 1.0), dF2 = random_matrix(this->rng, 1.0);
    const double a = inner(this->model.first_piola_differential(F, dF1), dF2);
    const double b = inner(this->model.first_piola_differential(F, dF2), dF1);
    EXPECT_NEAR(a, b, kInvarianceTolerance * (std::abs(a) + std::abs(b))) << "sample " << sample;
  }
}

TYPED_TEST(ConstitutiveModel, PrincipalStressIsTheStressInThePrincipalFrame) {
  // What the semidefinite stiffness is built from, for the models whose own P needs no SVD too.
  for (int sample = 0; sample < kSamples; ++sample) {
    const M F = sample % 2 ? large_deformation(this->rng)
                           : random_rotation(this->rng) * M::diag(1.2, 0.8, -0.5) * random_rotation(this->rng);
    const Svd3<double> svd = svd3(F);
    EXPECT_LE(relative_error(from_principal(svd.U, this->model.principal_stress(svd.sigma), svd.V),
                             this->model.first_piola(F)),
              kInvarianceTolerance)
        << "sample " << sample;
  }
}

// Whether a principal-space stiffness is already semidefinite: D symmetric with every principal
// minor ≥ 0 (Sylvester's criterion for semidefiniteness needs all seven, not only the leading ones)
// and every pair modulus ≥ 0, each up to rounding relative to the largest entry.
bool is_semidefinite(const PrincipalStiffness<double>& stiffness) {
  const M& D = stiffness.D;
  const double scale =
      std::max({max_abs(D), max_abs(M::diag(stiffness.symmetric_modulus)), max_abs(M::diag(stiffness.skew_modulus))});
  const double slack = 1e-9 * scale;
  if (max_abs(D - transpose(D)) > 1e-12 * scale) return false;
  for (int i = 0; i < 3; ++i) {
    if (D(i, i) < -slack || stiffness.symmetric_modulus[i] < -slack || stiffness.skew_modulus[i] < -slack) return false;
    const int j = (i + 1) % 3;
    if (D(i, i) * D(j, j) - D(i, j) * D(j, i) < -slack * scale) return false;
  }
  return determinant(D) >= -slack * scale * scale;
}

TYPED_TEST(ConstitutiveModel, DefiniteDifferentialIsTheDifferentialWhereTheStiffnessIsSemidefinite) {
  // Stretches just above rest and pure rotations: every model's stiffness is semidefinite for some of
  // them (the fluid's only at J = 1, where it resists volume change alone).
  int semidefinite = 0;
  for (int sample = 0; sample < kSamples; ++sample) {
    const M F = sample % 2
                    ? random_rotation(this->rng)
                    : random_rotation(this->rng) *
                          M::diag(uniform(this->rng, 1, 1.1), uniform(this->rng, 1, 1.1), uniform(this->rng, 1, 1.1)) *
                          random_rotation(this->rng);
    const PrincipalStiffness<double> stiffness = isotropic_stiffness(this->model, F);
    if (!is_semidefinite(stiffness)) continue;
    ++semidefinite;
    const M dF = random_matrix(this->rng, 1.0);
    EXPECT_LE(relative_error(stiffness.definite().apply(dF), this->model.first_piola_differential(F, dF)), 1e-9)
        << "sample " << sample;
  }
  EXPECT_GE(semidefinite, kSamples / 2);
}

TYPED_TEST(ConstitutiveModel, DefiniteDifferentialIsSemidefiniteUnderCompressionAndInversion) {
  int indefinite = 0;  // samples where the plain differential has δF : δP < 0, i.e. the fix had work to do
  for (int sample = 0; sample < 4 * kSamples; ++sample) {
    const M F = random_rotation(this->rng) *
                M::diag(uniform(this->rng, 0.2, 1.5), uniform(this->rng, 0.05, 1.0), uniform(this->rng, -0.8, 0.6)) *
                random_rotation(this->rng);
    const PrincipalStiffness<double> definite = isotropic_stiffness(this->model, F).definite();
    const M dF1 = random_matrix(this->rng, 1.0), dF2 = random_matrix(this->rng, 1.0);
    const M dP1 = definite.apply(dF1), dP2 = definite.apply(dF2);
    EXPECT_GE(inner(dF1, dP1), -1e-10 * frobenius_norm(dF1) * frobenius_norm(dP1)) << "sample " << sample;
    const double a = inner(dP1, dF2), b = inner(dP2, dF1);
    EXPECT_NEAR(a, b, kInvarianceTolerance * (std::abs(a) + std::abs(b))) << "sample " << sample;
    if (inner(dF1, this->model.first_piola_differential(F, dF1)) < 0) ++indefinite;
  }
  EXPECT_GT(indefinite, 0);
}

TYPED_TEST(ConstitutiveModel, RotatingTheDeformedShapeRotatesTheStress) {
  // Frame indifference: ψ(QF) = ψ(F), P(QF) = Q P(F).
  for (int sample = 0; sample < kSamples; ++sample) {
    const M F = large_deformation(this->rng);
    const M Q = random_rotation(this->rng);
    const double energy = this->model.energy_density(F);
    EXPECT_NEAR(this->model.energy_density(Q * F), energy, kInvarianceTolerance * std::abs(energy));
    EXPECT_LE(relative_error(this->model.first_piola(Q * F), Q * this->model.first_piola(F)), kInvarianceTolerance);
  }
}

TYPED_TEST(ConstitutiveModel, RotatingTheReferenceShapeRotatesTheStress) {
  // Isotropy: ψ(FQ) = ψ(F), P(FQ) = P(F) Q.
  for (int sample = 0; sample < kSamples; ++sample) {
    const M F = large_deformation(this->rng);
    const M Q = random_rotation(this->rng);
    const double energy = this->model.energy_density(F);
    EXPECT_NEAR(this->model.energy_density(F * Q), energy, kInvarianceTolerance * std::abs(energy));
    EXPECT_LE(relative_error(this->model.first_piola(F * Q), this->model.first_piola(F) * Q), kInvarianceTolerance);
  }
}

TYPED_TEST(ConstitutiveModel, InvertedAndDegenerateDeformationsGiveFiniteResults) {
  const M Q1 = random_rotation(this->rng), Q2 = random_rotation(this->rng);
  const std::vector<M> degenerate = {
      Q1 * M::diag(1.2, 0.8, -0.5) * Q2,        // inverted
      M::diag(1, 1, -1),                        // inverted with σ₁ = −σ₂
      -M::identity(),                           // point reflection
      Q1 * M::diag(1.5, 1, 1e-8) * Q2,          // nearly flat
      Q1 * M::diag(1.3, 0.7, 0) * Q2,           // rank 2
      M::outer(Vec(1, 2, -1), Vec(0.5, 0, 1)),  // rank 1
      M::zero(),
  };
  for (const M& F : degenerate) {
    const M dF = random_matrix(this->rng, 1.0);
    EXPECT_TRUE(is_finite(this->model.energy_density(F)));
    EXPECT_TRUE(is_finite(this->model.first_piola(F)));
    EXPECT_TRUE(is_finite(this->model.first_piola_differential(F, dF)));
    if constexpr (TypeParam::kPlastic) {
      EXPECT_TRUE(is_finite(this->model.project(F)));
    }
  }
}

// ---------------------------------------------------------------------------------------------------
// Model-specific behaviour.

TEST(HenckyStVK, CollapsedStretchCarriesTheStressOfTheClampedStretch) {
  const HenckyStVK<double> model{kSand.mu, kSand.lambda};
  std::mt19937_64 rng(7);
  const M U = random_rotation(rng), W = random_rotation(rng);
  const M at_clamp = model.first_piola(U * M::diag(1.2, 0.9, kMinHenckyStretch<double>) * transpose(W));
  for (double sigma : {1e-8, 0.0, -0.3}) {
    const M P = model.first_piola(U * M::diag(1.2, 0.9, sigma) * transpose(W));
    EXPECT_LE(relative_error(P, at_clamp), 1e-12) << "σ₂ = " << sigma;
  }
  // The collapsed direction is pushed back open: a strongly compressive principal stress.
  const Vec w2 = W.column(2);
  EXPECT_LT(dot(U.column(2), at_clamp * w2), -kSand.mu);
}

TEST(NeoHookean, InvertedStressIsTheGradientOfTheLinearlyContinuedEnergy) {
  const NeoHookean<double> model{kJelly.mu, kJelly.lambda};
  std::mt19937_64 rng(11);
  for (int sample = 0; sample < kSamples; ++sample) {
    const M F = random_rotation(rng) * M::diag(uniform(rng, 0.5, 2), uniform(rng, 0.5, 2), -uniform(rng, 0.2, 1)) *
                random_rotation(rng);
    ASSERT_LT(determinant(F), kMinVolumeRatio<double>);
    EXPECT_LE(relative_error(energy_gradient_by_differences(model, F), model.first_piola(F)),
              kFiniteDifferenceTolerance);
    const M dF = random_matrix(rng, 1.0);
    EXPECT_LE(relative_error(model.first_piola_differential(F, dF), stress_derivative_by_differences(model, F, dF)),
              kFiniteDifferenceTolerance);
  }
}

// A trial state F = U exp(ε) Vᵀ built from its principal frame and Hencky strain.
struct TrialState {
  M U, V;
  Vec strain;
  M F;
};

TrialState trial_state(std::mt19937_64& rng, double mean_low, double mean_high, double deviator_max) {
  TrialState state;
  state.U = random_rotation(rng);
  state.V = random_rotation(rng);
  // A random deviator (zero mean) of random length, plus a random mean strain.
  Vec deviator(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
  deviator -= Vec::constant((deviator[0] + deviator[1] + deviator[2]) / 3);
  deviator *= uniform(rng, 0, deviator_max) / norm(deviator);
  state.strain = deviator + Vec::constant(uniform(rng, mean_low, mean_high));
  const Vec stretch(std::exp(state.strain[0]), std::exp(state.strain[1]), std::exp(state.strain[2]));
  state.F = state.U * M::diag(stretch) * transpose(state.V);
  return state;
}

double sum(const Vec& v) { return v[0] + v[1] + v[2]; }
double deviator_norm(const Vec& strain) { return norm(strain - Vec::constant(sum(strain) / 3)); }

// The Hencky strain of a projected F in the trial's principal frame, and how far F is from diagonal there.
struct PrincipalView {
  Vec strain;
  double off_diagonal;
};

PrincipalView in_trial_frame(const TrialState& trial, const M& F) {
  const M D = transpose_times(trial.U, F * trial.V);
  PrincipalView view{Vec(std::log(D(0, 0)), std::log(D(1, 1)), std::log(D(2, 2))), 0.0};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (r != c) view.off_diagonal = std::max(view.off_diagonal, std::abs(D(r, c)));
  return view;
}

class DruckerPragerReturn : public testing::TestWithParam<double> {
 protected:
  double cohesion() const { return GetParam(); }
  DruckerPrager<double> model() const {
    return {{kSand.mu, kSand.lambda}, drucker_prager_alpha(kSandFrictionAngleDegrees), cohesion()};
  }
  // The yield function, written out from Klár et al. 2016 with the cohesion shift:
  // f(ε) = ‖ε̂‖ + α (3λ + 2μ)/(2μ) (tr ε − 3c); the admissible states are f ≤ 0 with tr ε ≤ 3c.
  double yield(const Vec& strain) const {
    const double alpha = std::sqrt(2.0 / 3.0) * 2 * std::sin(kSandFrictionAngleDegrees * kPi / 180) /
                         (3 - std::sin(kSandFrictionAngleDegrees * kPi / 180));
    return deviator_norm(strain) +
           alpha * (3 * kSand.lambda + 2 * kSand.mu) / (2 * kSand.mu) * (sum(strain) - 3 * cohesion());
  }
  std::vector<TrialState> trials() const {
    std::mt19937_64 rng(31);
    std::vector<TrialState> states;
    for (int sample = 0; sample < 400; ++sample) states.push_back(trial_state(rng, -0.4, 0.15, 0.4));
    return states;
  }
};

TEST_P(DruckerPragerReturn, StatesInsideTheConeAreUnchanged) {
  int inside = 0;
  for (const TrialState& trial : trials()) {
    if (!(yield(trial.strain) < -kYieldSurfaceTolerance && sum(trial.strain) < 3 * cohesion())) continue;
    ++inside;
    EXPECT_EQ(model().project(trial.F), trial.F);
  }
  EXPECT_GT(inside, 40);
}

TEST_P(DruckerPragerReturn, ShearedStatesReturnToTheConeSurfaceAtConstantVolume) {
  int sheared = 0;
  for (const TrialState& trial : trials()) {
    if (!(yield(trial.strain) > kYieldSurfaceTolerance && sum(trial.strain) < 3 * cohesion())) continue;
    ++sheared;
    const PrincipalView projected = in_trial_frame(trial, model().project(trial.F));
    EXPECT_LE(projected.off_diagonal, 1e-12);  // U and V are kept
    EXPECT_NEAR(yield(projected.strain), 0.0, kYieldSurfaceTolerance);
    EXPECT_NEAR(sum(projected.strain), sum(trial.strain), 1e-12);
  }
  EXPECT_GT(sheared, 40);
}

TEST_P(DruckerPragerReturn, ExpandedStatesProjectToTheConeTip) {
  int expanded = 0;
  for (const TrialState& trial : trials()) {
    if (!(sum(trial.strain) > 3 * cohesion())) continue;
    ++expanded;
    const M tip = std::exp(cohesion()) * times_transpose(trial.U, trial.V);
    EXPECT_LE(max_abs(model().project(trial.F) - tip), 1e-12);
  }
  EXPECT_GT(expanded, 40);
}

// The plastic strain a return reports is the Hencky strain it removed, and its F is project's.
template <class Model>
void expect_plastic_return_reports_the_removed_strain(const Model& model, const std::vector<TrialState>& trials) {
  int flowed = 0;
  for (const TrialState& trial : trials) {
    const PlasticReturn<double> plastic = model.plastic_return(trial.F);
    EXPECT_EQ(plastic.F, model.project(trial.F));
    const Vec removed = trial.strain - in_trial_frame(trial, plastic.F).strain;
    EXPECT_NEAR(plastic.strain, std::sqrt(removed[0] * removed[0] + removed[1] * removed[1] + removed[2] * removed[2]),
                1e-10);
    flowed += plastic.strain > 0.0;
  }
  EXPECT_GT(flowed, 40);
}

TEST_P(DruckerPragerReturn, ThePlasticStrainIsTheStrainRemoved) {
  expect_plastic_return_reports_the_removed_strain(model(), trials());
}

TEST_P(DruckerPragerReturn, EveryProjectedStateIsAdmissible) {
  for (const TrialState& trial : trials()) {
    const PrincipalView projected = in_trial_frame(trial, model().project(trial.F));
    EXPECT_LE(projected.off_diagonal, 1e-12);
    EXPECT_LE(yield(projected.strain), kYieldSurfaceTolerance);
    EXPECT_LE(sum(projected.strain), 3 * cohesion() + 1e-12);
  }
}

INSTANTIATE_TEST_SUITE_P(DruckerPrager, DruckerPragerReturn, testing::Values(0.0, 0.05),
                         [](const testing::TestParamInfo<double>& info) {
  return info.param == 0.0 ? std::string("Cohesionless") : std::string("Cohesive");
});

TEST(DruckerPrager, AlphaFollowsTheFrictionAngle) {
  EXPECT_EQ(drucker_prager_alpha(0.0), 0.0);
  const double s = std::sin(30 * kPi / 180);  // 1/2
  EXPECT_NEAR(drucker_prager_alpha(30.0), std::sqrt(2.0 / 3.0) * 2 * s / (3 - s), 1e-15);
}

class VonMisesReturn : public testing::Test {
 protected:
  const VonMises<double> model{{kPlasticine.mu, kPlasticine.lambda}, kPlasticineYieldStress};
  const double yield_radius = kPlasticineYieldStress / (2 * kPlasticine.mu);
  std::vector<TrialState> trials() const {
    std::mt19937_64 rng(37);
    std::vector<TrialState> states;
    for (int sample = 0; sample < 400; ++sample) states.push_back(trial_state(rng, -0.2, 0.2, 2.5 * yield_radius));
    return states;
  }
};

TEST_F(VonMisesReturn, StatesInsideTheYieldCylinderAreUnchanged) {
  int inside = 0;
  for (const TrialState& trial : trials()) {
    if (!(deviator_norm(trial.strain) < yield_radius - kYieldSurfaceTolerance)) continue;
    ++inside;
    EXPECT_EQ(model.project(trial.F), trial.F);
  }
  EXPECT_GT(inside, 40);
}

TEST_F(VonMisesReturn, ThePlasticStrainIsTheStrainRemoved) {
  expect_plastic_return_reports_the_removed_strain(model, trials());
}

TEST_F(VonMisesReturn, OutsideStatesReturnToTheYieldRadiusAtConstantVolume) {
  int outside = 0;
  for (const TrialState& trial : trials()) {
    if (!(deviator_norm(trial.strain) > yield_radius + kYieldSurfaceTolerance)) continue;
    ++outside;
    const PrincipalView projected = in_trial_frame(trial, model.project(trial.F));
    EXPECT_LE(projected.off_diagonal, 1e-12);  // U and V are kept
    EXPECT_NEAR(deviator_norm(projected.strain), yield_radius, kYieldSurfaceTolerance);
    EXPECT_NEAR(sum(projected.strain), sum(trial.strain), 1e-12);
  }
  EXPECT_GT(outside, 40);
}

TEST(WeaklyCompressibleFluid, ProjectionKeepsOnlyTheVolume) {
  const WeaklyCompressibleFluid<double> model{1e5};
  std::mt19937_64 rng(41);
  for (int sample = 0; sample < kSamples; ++sample) {
    const M F = large_deformation(rng);
    const M projected = model.project(F);
    const double stretch = std::cbrt(determinant(F));
    EXPECT_LE(max_abs(projected - M::diag(stretch, stretch, stretch)), 1e-15 * stretch);
    EXPECT_NEAR(determinant(projected), determinant(F), 1e-13 * determinant(F));
  }
  // A tiny but positive volume is kept as it is.
  EXPECT_NEAR(determinant(model.project(M::diag(1e-3, 1e-2, 1e-1))), 1e-6, 1e-19);
}

TEST(WeaklyCompressibleFluid, ProjectionOfANonPositiveVolumeIsTheSmallestVolume) {
  const WeaklyCompressibleFluid<double> model{1e5};
  const double stretch = std::cbrt(kMinVolumeRatio<double>);
  for (const M& F : {M::diag(1, 1, -0.5), M::zero()})
    EXPECT_LE(max_abs(model.project(F) - M::diag(stretch, stretch, stretch)), 1e-15);
}

TEST(WeaklyCompressibleFluid, KirchhoffStressIsAPressure) {
  const double lambda = 1e5;
  const WeaklyCompressibleFluid<double> model{lambda};
  std::mt19937_64 rng(43);
  for (int sample = 0; sample < kSamples; ++sample) {
    const M F = large_deformation(rng);
    const double J = determinant(F);
    const double pressure = lambda * J * (J - 1);
    const M tau = times_transpose(model.first_piola(F), F);
    EXPECT_LE(max_abs(tau - M::diag(pressure, pressure, pressure)), 1e-12 * std::abs(pressure));
  }
}

TEST(Lame, ClosedFormForYoungModulus1e5AndPoissonRatio0p2) {
  const Lame<double> lame = lame_from_young_poisson(1e5, 0.2);
  EXPECT_NEAR(lame.mu, 1e5 / 2.4, 1e-10);                    // 41666.67
  EXPECT_NEAR(lame.lambda, 1e5 * 0.2 / (1.2 * 0.6), 1e-10);  // 27777.78
}

// ---------------------------------------------------------------------------------------------------
// MaterialParams and the dispatchers.

std::vector<MaterialParams<double>> every_material() {
  return {MaterialParams<double>::fixed_corotated(kJelly),
          MaterialParams<double>::neo_hookean(kJelly),
          MaterialParams<double>::hencky_stvk(kSand),
          MaterialParams<double>::drucker_prager(kSand, kSandFrictionAngleDegrees, 0.0),
          MaterialParams<double>::von_mises(kPlasticine, kPlasticineYieldStress),
          MaterialParams<double>::weakly_compressible_fluid(kJelly.lambda)};
}

TEST(MaterialDispatch, ForwardsToTheModelItDescribes) {
  std::mt19937_64 rng(47);
  const M F = large_deformation(rng), dF = random_matrix(rng, 1.0);
  const auto check = [&](const MaterialParams<double>& params, const auto& model) {
    EXPECT_EQ(energy_density(params, F), model.energy_density(F));
    EXPECT_EQ(first_piola(params, F), model.first_piola(F));
    EXPECT_EQ(first_piola_differential(params, F, dF), model.first_piola_differential(F, dF));
    EXPECT_EQ(definite_stiffness(params, F).apply(dF), isotropic_stiffness(model, F).definite().apply(dF));
  };
  const std::vector<MaterialParams<double>> materials = every_material();
  check(materials[0], TestModel<FixedCorotated<double>>::make());
  check(materials[1], TestModel<NeoHookean<double>>::make());
  check(materials[2], TestModel<HenckyStVK<double>>::make());
  check(materials[3], TestModel<DruckerPrager<double>>::make());
  check(materials[4], TestModel<VonMises<double>>::make());
  check(materials[5], WeaklyCompressibleFluid<double>{kJelly.lambda});
  EXPECT_EQ(project_plastic(materials[3], F), TestModel<DruckerPrager<double>>::make().project(F));
  EXPECT_EQ(project_plastic(materials[4], F), TestModel<VonMises<double>>::make().project(F));
  EXPECT_EQ(project_plastic(materials[5], F), WeaklyCompressibleFluid<double>{kJelly.lambda}.project(F));
}

TEST(MaterialDispatch, ElasticModelsProjectToThemselves) {
  std::mt19937_64 rng(53);
  const M F = large_deformation(rng);
  for (const MaterialParams<double>& params : every_material())
    if (!is_plastic(params.model)) {
      EXPECT_EQ(project_plastic(params, F), F);
    }
}

TEST(MaterialDispatch, IsPlasticForTheReturnMapsAndTheFluid) {
  EXPECT_FALSE(is_plastic(MaterialModel::FixedCorotated));
  EXPECT_FALSE(is_plastic(MaterialModel::NeoHookean));
  EXPECT_FALSE(is_plastic(MaterialModel::HenckyStVK));
  EXPECT_TRUE(is_plastic(MaterialModel::DruckerPrager));
  EXPECT_TRUE(is_plastic(MaterialModel::VonMises));
  EXPECT_TRUE(is_plastic(MaterialModel::WeaklyCompressibleFluid));
}

}  // namespace
}  // namespace romp::material
