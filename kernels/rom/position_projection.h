// The position projection of the ROM's online step (ROM paper, Alg. 6): x̂_{n+1} = argmin_y
// Σ_p ‖x_p − g(X_p; y)‖² over the samples' trial positions x_p, by Gauss–Newton with a backtracking line
// search, where the samples are.
//
// Why on the device. Every Gauss–Newton linearisation needs g and ∂g/∂x̂ at the samples, and every
// step of the line search decides from a cost what to try next; run from the host, each decision is a
// blocking round trip (the H200 spent 5.4–10.1 ms per substep there, ../shared/gpu-runs/2026-12-04-h200).
// Here the decisions are made by one thread next to the data (GaussNewtonStep) and, on CUDA for the
// sample counts hyper-reduction uses (m ≤ kOneBlockSamples), the whole iteration is one block: a launch
// per projection and no transfer. Otherwise the iteration runs as launches from the host, which reads
// each decision where it is: in place on the CPU, downloaded on CUDA and, for sample sets above
// kOneBlockSamples (every point sampled), on either backend alike, so that traffic counts agree.
#pragma once

#include <cmath>
#include <cstdint>

#include "kernels/core/exec.h"
#include "kernels/core/hd.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/rom/deformation_map_eval.h"
#include "kernels/rom/reduced_dynamics.h"

namespace romp::rom {

struct GaussNewtonOptions {
  int iterations = 10;      // at most this many steps; more counts as unconverged
  double tolerance = 1e-6;  // converged when a step changes y by ≤ tolerance × (1 + |y|)
};

// Samples up to which one CUDA block runs the whole projection, a thread per sample (hyper-reduction uses
// tens: the paper's 10 or 50, and 5 per kinematic boundary).
inline constexpr Index kOneBlockSamples = 128;

// The line search halves the step at most this often before deciding that no descent is left.
inline constexpr int kLineSearchHalvings = 10;

// Converged, too, where the linear model promises less than the cost's float resolution. A residual r
// against positions t computed in float (g carries a few ulps of rounding, kPositionRounding of |t|)
// is known to about kPositionRounding |t| / |r| of itself: Σ‖r‖² to 2 kPositionRounding √(Σ‖r‖² Σ‖t‖²).
// Smaller promises are rounding, and the steps that chase them wander in it: on the tower (residuals of
// 10 µm at positions of 0.5 m) 17–38 linearisations per substep, none of which moved x̂ beyond its noise.
inline constexpr double kPositionRounding = 2.4e-7;  // 4 ulps of float
inline constexpr double kCostResolution = 1e-6;      // and at least this fraction of the cost

// Where one projection stands, in device memory; written by one thread only.
struct GaussNewtonState {
  enum Outcome : std::int32_t { kRunning = 0, kConverged = 1, kUnconverged = 2, kSingular = 3 };
  float y[kMaxMapLatent];       // the accepted iterate
  float trial[kMaxMapLatent];   // where the next linearisation is evaluated
  double delta[kMaxMapLatent];  // the Gauss–Newton direction at y
  double cost;                  // Σ ‖x − g(X; y)‖²
  double alpha;                 // the line search's step fraction
  double target_norm2;          // Σ ‖t‖² over the samples' target positions
  std::int32_t iteration, halving, started, outcome;
  // Over the state's life (never reset by a start): projections that stopped at the iteration limit, and
  // linearisations (evaluations of g and ∂g/∂x̂ at the samples) taken.
  std::int64_t unconverged_total, linearisations_total;
};

// The decisions of one projection, shared by every path: start from a guess, then take each
// linearisation at `trial` (its solved normal equations) and choose the next trial.
struct GaussNewtonStep {
  int latent;
  GaussNewtonOptions options;

  // A new projection from the guess in s.trial, with s.target_norm2 set.
  ROMP_HD void start(GaussNewtonState& s) const {
    s.started = 0;
    s.outcome = GaussNewtonState::kRunning;
  }

  // `solution`: the Gauss–Newton direction at trial (or null: its system is singular); `cost`: the squared
  // residual there; `predicted_decrease`: what the full step would take off it in the linear model
  // (δᵀ A δ). Returns the outcome; while kRunning, trial holds the next point to linearise at.
  ROMP_HD std::int32_t take(GaussNewtonState& s, const double* solution, double cost, double predicted_decrease) const {
    const int r = latent;
    ++s.linearisations_total;
    if (!solution) return s.outcome = GaussNewtonState::kSingular;
    if (!s.started) {  // the first linearisation: at the guess
      accept(s, solution, cost);
      s.iteration = 0;
      if (predicted_decrease <= resolution(s, cost)) return s.outcome = GaussNewtonState::kConverged;
    } else if (cost <= s.cost) {  // the step descends
      double step = 0.0;
      for (int j = 0; j < r; ++j) {
        const double change = double(s.trial[j]) - double(s.y[j]);
        step += change * change;
      }
      accept(s, solution, cost);
      if (std::sqrt(step) <= tolerance_at(s) || predicted_decrease <= resolution(s, cost))
        return s.outcome = GaussNewtonState::kConverged;
      if (++s.iteration >= options.iterations) {
        ++s.unconverged_total;
        return s.outcome = GaussNewtonState::kUnconverged;
      }
    } else if (++s.halving > kLineSearchHalvings || 0.5 * s.alpha * direction_length(s) <= tolerance_at(s)) {
      // No descent along the direction, or none left but below the tolerance, which would stop at once:
      // y is the minimum to float precision.
      return s.outcome = GaussNewtonState::kConverged;
    } else {
      s.alpha *= 0.5;
      return next_trial(s);
    }
    s.halving = 0;
    s.alpha = 1.0;
    return next_trial(s);
  }

  // After the last take: x̂_{n+1} = y into `latent` ([x̂ | v̂ | status]) and [x̂_n | x̂_{n+1}] into
  // `history`; a singular system leaves both and marks the status.
  ROMP_HD void finish(const GaussNewtonState& s, float* latent_state, float* history) const {
    const int r = latent;
    if (s.outcome == GaussNewtonState::kSingular) {
      latent_state[2 * r] = kLatentSingular;
      return;
    }
    for (int j = 0; j < r; ++j) {
      history[j] = history[r + j];
      history[r + j] = s.y[j];
      latent_state[j] = s.y[j];
    }
  }

 private:
  ROMP_HD void accept(GaussNewtonState& s, const double* solution, double cost) const {
    for (int j = 0; j < latent; ++j) {
      s.y[j] = s.trial[j];
      s.delta[j] = solution[j];
    }
    s.cost = cost;
    s.started = 1;
  }
  // Cost changes smaller than this are float rounding (see kPositionRounding).
  ROMP_HD static double resolution(const GaussNewtonState& s, double cost) {
    return kCostResolution * cost + 2.0 * kPositionRounding * std::sqrt(cost * s.target_norm2);
  }
  // Steps shorter than this change nothing the projection resolves.
  ROMP_HD double tolerance_at(const GaussNewtonState& s) const {
    double norm = 0.0;
    for (int j = 0; j < latent; ++j) norm += double(s.y[j]) * double(s.y[j]);
    return options.tolerance * (1.0 + std::sqrt(norm));
  }
  ROMP_HD double direction_length(const GaussNewtonState& s) const {
    double length = 0.0;
    for (int j = 0; j < latent; ++j) length += s.delta[j] * s.delta[j];
    return std::sqrt(length);
  }
  ROMP_HD std::int32_t next_trial(GaussNewtonState& s) const {
    for (int j = 0; j < latent; ++j) s.trial[j] = float(double(s.y[j]) + s.alpha * s.delta[j]);
    return s.outcome = GaussNewtonState::kRunning;
  }
};

// The inputs and scratch of one projection over m samples, on exec's backend.
struct PositionProjection {
  Vec3Planes<const float> X;       // the samples' reference positions
  Vec3Planes<const float> target;  // their trial positions
  Vec3Planes<float> model;         // scratch: g(X; trial), m
  Span<float> dg_dxhat;            // scratch: ∂g/∂x̂ at trial, 3 r planes of m
  Span<double> system;             // scratch: r² + r + 1 (normal_equations' layout)
  // [x̂_{n−1} | x̂_n] (2 r), advanced to [x̂_n | x̂_{n+1}] when the projection ends.
  Span<float> history;
  // [x̂ | v̂ | status] (2 r + 1, as advance_latent leaves it): x̂ in, the guess unless `extrapolate`; out,
  // x̂_{n+1}. A singular system sets the status to kLatentSingular and leaves x̂ as it came in.
  Span<float> latent;
  Span<GaussNewtonState> state;  // 1
};

// Gauss–Newton from the guess 2 x̂_n − x̂_{n−1} (`extrapolate`) or from latent's x̂ (the first step).
// Queued on exec; reads nothing back while m ≤ kOneBlockSamples, and one decision per linearisation above.
// The map is evaluated as evaluate_deformation_map does (MapKernel::Fastest).
void project_positions(const Exec& exec, const DeformationMapView<float>& map, const GaussNewtonOptions& options,
                       bool extrapolate, const PositionProjection& projection);

}  // namespace romp::rom
