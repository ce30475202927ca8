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
  // `state`: 2 r + 1 floats on `backend` that hold [x̂ | v̂ | status], owned by the caller (ReducedSim keeps
  // them where the substep's failure slots are read back, StepInputs::reserve_readback), set here.
  LatentProjection(Backend backend, const std::vector<float>& initial_xhat, bool positions,
                   rom::GaussNewtonOptions options, Span<float> state);

  Span<float> xhat() { return latent_.subspan(0, latent_size_); }
  Span<float> vhat() { return latent_.subspan(latent_size_, latent_size_); }

  // v̂ as the least-squares fit of velocities `v` (3 planes of n) through ∂g/∂x̂ at the n points (Eq. 28);
  // returns it, or an empty vector when the normal equations are singular.
  std::vector<float> fit_velocity(const Exec& exec, Span<const float> dg_dxhat, Vec3Planes<const float> v);

  // v̂_{n+1} from the samples' trial velocities on the tangent space at x̂_n (∂g/∂x̂ there), and x̂_{n+1}
  // (Gauss–Newton from 2 x̂_n − x̂_{n−1}, from x̂_n + Δt v̂_{n+1} the first time, or x̂_n + Δt v̂_{n+1}).
  void project(const Exec& exec, const DeformationMap& map, SampleSet& samples, float dt);

  // [x̂ | v̂ | status] (a download); status rom::kLatentSolved or rom::kLatentSingular.
  std::vector<float> read(const Exec& exec) const { return download(exec.backend, latent_, exec.stream); }
  // The Gauss–Newton totals (a download); zero without the position projection.
  rom::GaussNewtonState gauss_newton_state(const Exec& exec) const;

 private:
  int latent_size_;
  bool positions_;
  rom::GaussNewtonOptions options_;
  bool has_previous_ = false;
  Span<float> latent_;           // [x̂ | v̂ | status]
  DeviceBuffer<double> system_;  // r² + r + 1: rom::normal_equations' layout
  // Position–velocity: [x̂_{n−1} | x̂_n] and the Gauss–Newton state (rom::project_positions).
  DeviceBuffer<float> history_;
  DeviceBuffer<rom::GaussNewtonState> state_;
};

}  // namespace romp::engine
