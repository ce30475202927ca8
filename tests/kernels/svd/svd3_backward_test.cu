// svd3/polar3 backward passes match central finite differences in double, and stay finite at repeated
// singular values; run through the batched launchers on the test binary's backend.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/math/mat3.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/svd/svd3_batched.h"
#include "tests/kernels/svd/svd_test_matrices.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

// The issue's bound for separated singular values: relative error in the Frobenius norm.
constexpr double kGradientTolerance = 1e-6;
// Central-difference step relative to ‖F‖: truncation error O(h²) and rounding O(ε/h) both ≈ 1e-10.
constexpr double kRelativeStep = 1e-5;
// Matrices per class.
constexpr int kSamples = 200;

std::string describe(const Mat3<double>& a) {
  std::string text = "[";
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) text += std::to_string(a(r, c)) + (c < 2 ? ", " : r < 2 ? "; " : "]");
  return text;
}

// A batch of n 3x3 matrices (or 3-vectors) in planes on the test backend.
struct Planes {
  Planes(const Exec& exec, Index count, int components) : count(count), buffer(exec.backend, components * count) {}
  Index count;
  DeviceBuffer<double> buffer;
  Mat3Planes<double> matrices() { return {buffer.data(), count}; }
  Vec3Planes<double> vectors() { return {buffer.data(), count}; }
};

Planes upload(const Exec& exec, const std::vector<Mat3<double>>& matrices) {
  const Index n = Index(matrices.size());
  std::vector<double> host(9 * matrices.size());
  Mat3Planes<double> view(host.data(), n);
  for (Index i = 0; i < n; ++i) view.store(i, matrices[i]);
  Planes planes(exec, n, 9);
  planes.buffer.copy_from_host(Span<const double>(host.data(), Index(host.size())), exec.stream);
  return planes;
}
Planes upload(const Exec& exec, const std::vector<Vec3<double>>& vectors) {
  const Index n = Index(vectors.size());
  std::vector<double> host(3 * vectors.size());
  Vec3Planes<double> view(host.data(), n);
  for (Index i = 0; i < n; ++i) view.store(i, vectors[i]);
  Planes planes(exec, n, 3);
  planes.buffer.copy_from_host(Span<const double>(host.data(), Index(host.size())), exec.stream);
  return planes;
}
std::vector<Mat3<double>> download_matrices(const Exec& exec, const Planes& planes) {
  std::vector<double> host = planes.buffer.to_host(exec.stream);
  Mat3Planes<const double> view(host.data(), planes.count);
  std::vector<Mat3<double>> matrices;
  for (Index i = 0; i < planes.count; ++i) matrices.push_back(view.load(i));
  return matrices;
}
std::vector<Vec3<double>> download_vectors(const Exec& exec, const Planes& planes) {
  std::vector<double> host = planes.buffer.to_host(exec.stream);
  Vec3Planes<const double> view(host.data(), planes.count);
  std::vector<Vec3<double>> vectors;
  for (Index i = 0; i < planes.count; ++i) vectors.push_back(view.load(i));
  return vectors;
}

struct Decomposition {
  std::vector<Mat3<double>> U, V;
  std::vector<Vec3<double>> sigma;
};

Decomposition svd(const std::vector<Mat3<double>>& inputs) {
  const Exec& exec = test::exec();
  const Index n = Index(inputs.size());
  Planes F = upload(exec, inputs), U(exec, n, 9), sigma(exec, n, 3), V(exec, n, 9);
  svd3_batched(exec, F.matrices(), U.matrices(), sigma.vectors(), V.matrices());
  return {download_matrices(exec, U), download_matrices(exec, V), download_vectors(exec, sigma)};
}

// The incoming gradients of a test loss L = ⟨W_U, U⟩ + ⟨w_σ, σ⟩ + ⟨W_V, V⟩ (or ⟨W_R, R⟩ + ⟨W_S, S⟩).
struct LossWeights {
  Mat3<double> first, second;  // W_U and W_V, or W_R and W_S
  Vec3<double> sigma;          // w_σ (SVD only)
};

LossWeights random_weights(test::MatrixSampler& sampler) {
  return {sampler.gaussian(), sampler.gaussian(),
          Vec3<double>(sampler.uniform(-1, 1), sampler.uniform(-1, 1), sampler.uniform(-1, 1))};
}

std::vector<Mat3<double>> svd_backward(const Decomposition& at, const std::vector<LossWeights>& weights) {
  const Exec& exec = test::exec();
  const Index n = Index(weights.size());
  std::vector<Mat3<double>> dU, dV;
  std::vector<Vec3<double>> dsigma;
  for (const LossWeights& w : weights) {
    dU.push_back(w.first);
    dV.push_back(w.second);
    dsigma.push_back(w.sigma);
  }
  Planes U = upload(exec, at.U), sigma = upload(exec, at.sigma), V = upload(exec, at.V);
  Planes dU_planes = upload(exec, dU), dsigma_planes = upload(exec, dsigma), dV_planes = upload(exec, dV);
  Planes dF(exec, n, 9);
  svd3_backward_batched(exec, U.matrices(), sigma.vectors(), V.matrices(), dU_planes.matrices(),
                        dsigma_planes.vectors(), dV_planes.matrices(), dF.matrices());
  return download_matrices(exec, dF);
}

std::vector<Mat3<double>> polar_backward(const std::vector<Mat3<double>>& inputs,
                                         const std::vector<LossWeights>& weights) {
  const Exec& exec = test::exec();
  const Index n = Index(inputs.size());
  std::vector<Mat3<double>> dR, dS;
  for (const LossWeights& w : weights) {
    dR.push_back(w.first);
    dS.push_back(w.second);
  }
  Planes F = upload(exec, inputs), dR_planes = upload(exec, dR), dS_planes = upload(exec, dS), dF(exec, n, 9);
  polar3_backward_batched(exec, F.matrices(), dR_planes.matrices(), dS_planes.matrices(), dF.matrices());
  return download_matrices(exec, dF);
}

// Each F and its 18 perturbations F ± h e_r e_cᵀ, in one batch: index 19 i is F_i, 19 i + 1 + 2 (3r + c)
// is the + perturbation of entry (r, c), the next one the - perturbation.
constexpr int kStencil = 19;
std::vector<Mat3<double>> with_perturbations(const std::vector<Mat3<double>>& inputs, std::vector<double>& steps) {
  std::vector<Mat3<double>> batch;
  for (const Mat3<double>& F : inputs) {
    const double h = kRelativeStep * frobenius_norm(F);
    steps.push_back(h);
    batch.push_back(F);
    for (int e = 0; e < 9; ++e) {
      for (double sign : {1.0, -1.0}) {
        Mat3<double> perturbed = F;
        perturbed(e / 3, e % 3) += sign * h;
        batch.push_back(perturbed);
      }
    }
  }
  return batch;
}

// Central differences of the SVD loss. The singular vectors of a perturbed F are aligned with the
// unperturbed ones (the pair (uₖ, vₖ) flipped together, which leaves F unchanged), so the loss sees
// one smooth branch of the decomposition.
std::vector<Mat3<double>> svd_loss_differences(const std::vector<Mat3<double>>& inputs,
                                               const std::vector<LossWeights>& weights) {
  std::vector<double> steps;
  const Decomposition all = svd(with_perturbations(inputs, steps));
  std::vector<Mat3<double>> gradients;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const std::size_t base = kStencil * i;
    auto loss = [&](std::size_t j) {
      double value = dot(weights[i].sigma, all.sigma[j]);
      for (int k = 0; k < 3; ++k) {
        const double flip = dot(all.U[j].column(k), all.U[base].column(k)) < 0 ? -1.0 : 1.0;
        value += flip * (dot(weights[i].first.column(k), all.U[j].column(k)) +
                         dot(weights[i].second.column(k), all.V[j].column(k)));
      }
      return value;
    };
    Mat3<double> gradient;
    for (int e = 0; e < 9; ++e)
      gradient(e / 3, e % 3) = (loss(base + 1 + 2 * e) - loss(base + 2 + 2 * e)) / (2 * steps[i]);
    gradients.push_back(gradient);
  }
  return gradients;
}

std::vector<Mat3<double>> polar_loss_differences(const std::vector<Mat3<double>>& inputs,
                                                 const std::vector<LossWeights>& weights) {
  std::vector<double> steps;
  const Decomposition all = svd(with_perturbations(inputs, steps));
  std::vector<Mat3<double>> gradients;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    auto loss = [&](std::size_t j) {
      const Mat3<double> R = times_transpose(all.U[j], all.V[j]);
      const Mat3<double> S = times_transpose(all.V[j] * Mat3<double>::diag(all.sigma[j]), all.V[j]);
      return inner(weights[i].first, R) + inner(weights[i].second, S);
    };
    Mat3<double> gradient;
    for (int e = 0; e < 9; ++e) {
      const std::size_t plus = kStencil * i + 1 + 2 * e;
      gradient(e / 3, e % 3) = (loss(plus) - loss(plus + 1)) / (2 * steps[i]);
    }
    gradients.push_back(gradient);
  }
  return gradients;
}

void expect_match(const std::string& what, const std::vector<Mat3<double>>& inputs,
                  const std::vector<Mat3<double>>& analytic, const std::vector<Mat3<double>>& differences) {
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    ASSERT_LE(frobenius_norm(analytic[i] - differences[i]), kGradientTolerance * frobenius_norm(differences[i]))
        << what << " #" << i << " F = " << describe(inputs[i]);
  }
}

std::vector<LossWeights> random_weights(test::MatrixSampler& sampler, std::size_t count) {
  std::vector<LossWeights> weights;
  for (std::size_t i = 0; i < count; ++i) weights.push_back(random_weights(sampler));
  return weights;
}

// Singular values at least 5% apart (relative to σ₀), in random order and sign.
Mat3<double> separated(test::MatrixSampler& sampler, double sign_of_det) {
  const double s0 = sampler.uniform(1.5, 2.0), s1 = sampler.uniform(0.8, 1.4), s2 = sampler.uniform(0.1, 0.7);
  return sampler.with_singular_values(s1, sign_of_det * s2, s0);
}

TEST(Svd3Backward, MatchesCentralDifferencesForSeparatedSingularValues) {
  test::MatrixSampler sampler(21);
  std::vector<Mat3<double>> inputs;
  for (int i = 0; i < kSamples; ++i) inputs.push_back(separated(sampler, 1.0));
  const std::vector<LossWeights> weights = random_weights(sampler, inputs.size());
  expect_match("separated", inputs, svd_backward(svd(inputs), weights), svd_loss_differences(inputs, weights));
}

TEST(Svd3Backward, MatchesCentralDifferencesForInvertedElements) {
  test::MatrixSampler sampler(22);
  std::vector<Mat3<double>> inputs;
  for (int i = 0; i < kSamples; ++i) inputs.push_back(separated(sampler, -1.0));
  const std::vector<LossWeights> weights = random_weights(sampler, inputs.size());
  expect_match("inverted", inputs, svd_backward(svd(inputs), weights), svd_loss_differences(inputs, weights));
}

TEST(Polar3Backward, MatchesCentralDifferences) {
  test::MatrixSampler sampler(23);
  std::vector<Mat3<double>> inputs;
  for (int i = 0; i < kSamples; ++i) inputs.push_back(separated(sampler, sampler.random_sign()));
  const std::vector<LossWeights> weights = random_weights(sampler, inputs.size());
  expect_match("polar", inputs, polar_backward(inputs, weights), polar_loss_differences(inputs, weights));
}

TEST(Polar3Backward, ExactThroughRepeatedSingularValues) {
  // R and S are smooth functions of F where σᵢ = σⱼ > 0; only σᵢ + σⱼ enters their gradient, so no
  // regularisation applies and central differences must match.
  test::MatrixSampler sampler(24);
  std::vector<Mat3<double>> inputs;
  for (int i = 0; i < kSamples; ++i) {
    const double a = sampler.uniform(0.5, 2.0);
    inputs.push_back(i % 2 ? sampler.with_singular_values(a, a, sampler.uniform(0.1, 0.4))
                           : sampler.with_singular_values(a, a, a));
  }
  const std::vector<LossWeights> weights = random_weights(sampler, inputs.size());
  expect_match("polar, repeated σ", inputs, polar_backward(inputs, weights), polar_loss_differences(inputs, weights));
}

TEST(Svd3Backward, FiniteForRepeatedAndDegenerateSingularValues) {
  test::MatrixSampler sampler(25);
  std::vector<Mat3<double>> inputs = {Mat3<double>::identity(), Mat3<double>::zero(), Mat3<double>::diag(1, 1, -1),
                                      Mat3<double>::diag(2, 2, 1), 1e-30 * Mat3<double>::identity()};
  for (int i = 0; i < kSamples; ++i) {
    const double a = sampler.uniform(0.5, 2.0);
    switch (i % 5) {
      case 0: inputs.push_back(sampler.with_singular_values(a, a, sampler.uniform(0.1, 0.4))); break;
      case 1: inputs.push_back(sampler.with_singular_values(a, a * (1 + 1e-12), a * (1 - 1e-12))); break;
      case 2:
        inputs.push_back(sampler.with_singular_values(a, sampler.uniform(0.1, 0.4), -sampler.uniform(0.1, 0.4)));
        break;
      case 3: inputs.push_back(sampler.with_singular_values(a, a, -a)); break;  // σ₁ + σ₂ = 0
      default: inputs.push_back(sampler.with_singular_values(a, 0, 0)); break;  // rank 1
    }
  }
  const std::vector<LossWeights> weights = random_weights(sampler, inputs.size());
  const std::vector<Mat3<double>> from_svd = svd_backward(svd(inputs), weights);
  const std::vector<Mat3<double>> from_polar = polar_backward(inputs, weights);
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    ASSERT_TRUE(std::isfinite(squared_frobenius_norm(from_svd[i]))) << describe(inputs[i]);
    ASSERT_TRUE(std::isfinite(squared_frobenius_norm(from_polar[i]))) << describe(inputs[i]);
  }
}

TEST(Svd3Backward, SingularValueGradientIsUTimesVTransposeWithoutRegularisation) {
  // dσₖ/dF = uₖ vₖᵀ holds also for repeated σ: with zero gradients for U and V the clamp never acts.
  test::MatrixSampler sampler(26);
  const std::vector<Mat3<double>> inputs = {Mat3<double>::identity(), sampler.with_singular_values(2, 2, 1),
                                            sampler.with_singular_values(1, 0.5, -0.5)};
  std::vector<LossWeights> weights;
  for (std::size_t i = 0; i < inputs.size(); ++i)
    weights.push_back({Mat3<double>::zero(), Mat3<double>::zero(), Vec3<double>(0.3, -1.2, 0.7)});
  const Decomposition at = svd(inputs);
  const std::vector<Mat3<double>> gradients = svd_backward(at, weights);
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const Mat3<double> expected = times_transpose(at.U[i] * Mat3<double>::diag(weights[i].sigma), at.V[i]);
    ASSERT_LE(frobenius_norm(gradients[i] - expected), 1e-14) << describe(inputs[i]);
  }
}

}  // namespace
}  // namespace romp
