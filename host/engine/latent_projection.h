// LatentProjection: the reduced state [x̂ | v̂ | status] on the device and the projections that advance
// it from the samples' MPM update (ROM paper, Alg. 6 and 7), solved where the system is so that a
// substep reads back nothing but the new state.
#pragma once

#include <cstdint>
#include <vector>

#include "host/engine/deformation_map.h"
#include "host/engine/sample_set.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/rom/position_projection.h"

namespace romp::engine {

class LatentProjection {
 public:
  // `positions`: also x̂ by Gauss–Newton on the trial positions (Alg. 6), else x̂ += Δt v̂ (Alg. 7).
  LatentProjection(Backend backend, const std::vector<float>& initial_xhat, bool positions,
                   rom::GaussNewtonOptions options);

  Span<float> xhat() { return latent_.span().subspan(0, latent_size_); }
  Span<float> vhat() { return latent_.span().subspan(latent_size_, latent_size_); }
  // [x̂ | v̂ | status] on the device; status rom::kLatentSolved or rom::kLatentSingular.
  Span<const float> state() const { return latent_.span(); }

  // v̂ as the least-squares fit of velocities `v` (3 planes of n) through ∂g/∂x̂ at the n points (Eq. 28);
  // returns it, or an empty vector when the normal equations are singular.
  std::vector<float> fit_velocity(const Exec& exec, Span<const float> dg_dxhat, Vec3Planes<const float> v);

  // v̂_{n+1} from the samples' trial velocities on the tangent space at x̂_n (∂g/∂x̂ there), and x̂_{n+1}
  // (Gauss–Newton from 2 x̂_n − x̂_{n−1}, from x̂_n + Δt v̂_{n+1} the first time, or x̂_n + Δt v̂_{n+1}).
  void project(const Exec& exec, const DeformationMap& map, SampleSet& samples, float dt);
  // Whether projecting `samples` samples runs on the device alone (the position projection's Gauss–Newton in
  // one block; more samples read each decision back).
  bool projects_on_device(Index samples) const { return !positions_ || samples <= rom::kOneBlockSamples; }

  // The Gauss–Newton totals (a download); zero without the position projection.
  rom::GaussNewtonState gauss_newton_state(const Exec& exec) const;

 private:
  int latent_size_;
  bool positions_;
  rom::GaussNewtonOptions options_;
  bool has_previous_ = false;
  DeviceBuffer<float> latent_;   // [x̂ | v̂ | status]
  DeviceBuffer<double> system_;  // r² + r + 1: rom::normal_equations' layout
  // Position–velocity: [x̂_{n−1} | x̂_n] and the Gauss–Newton state (rom::project_positions).
  DeviceBuffer<float> history_;
  DeviceBuffer<rom::GaussNewtonState> state_;
};

}  // namespace romp::engine
