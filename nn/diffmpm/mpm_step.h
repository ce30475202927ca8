// The differentiable MLS-MPM substep as a LibTorch autograd function whose backward runs romp's adjoint kernels.
//
// Tensors use the engine's planes (as nn/svd_ops.h): n particles' vectors are [3, n], matrices
// [9, n] with row 3 r + c holding entry (r, c). float32 (training) or float64 (gradient checks), on
// the CPU or a CUDA device; the kernels run on the tensors' device and PyTorch's current stream.
#pragma once

#include <torch/torch.h>

#include <array>

#include "kernels/mpm/domain_config.h"

namespace romp::nn::diffmpm {

// The state a rollout carries from step to step: x, v [3, n]; C (APIC affine velocity), F (elastic
// deformation gradient) [9, n].
struct MpmState {
  torch::Tensor x, v, C, F;
};

// Scene constants of a differentiable simulation: every substep takes fixed_dt; the walls are
// frictionless, and cfl and max_dt (the engine's CFL step) do not apply. Defaults: the training scene
// of Ma et al. 2023 (unit box on 20³ cells, dt = 5e-4 s, gravity 9.8 m/s², free-slip walls within 3 cells).
struct DiffMpmConfig : mpm::DomainConfig<double> {
  DiffMpmConfig() {
    fixed_dt = 5e-4;
    dx = 0.05;
    domain_cells = {20, 20, 20};
    gravity = Vec3<double>(0.0, -9.8, 0.0);
  }
};

class DiffMpm {
 public:
  // mass and volume [n] (kg, reference m³) fix the particle count, dtype and device of every state.
  DiffMpm(const DiffMpmConfig& config, torch::Tensor mass, torch::Tensor volume);

  // One substep (Ma et al. 2023, Alg. 3) with the first Piola–Kirchhoff stress P [9, n] at state.F:
  // returns (x', v', C', F_trial'), differentiable with respect to state.x, v, C, F and P.
  MpmState step(const MpmState& state, const torch::Tensor& P) const;

  const DiffMpmConfig& config() const { return config_; }
  const torch::Tensor& mass() const { return mass_; }
  const torch::Tensor& volume() const { return volume_; }
  int64_t particle_count() const { return mass_.size(0); }

 private:
  DiffMpmConfig config_;
  torch::Tensor mass_, volume_;
};

}  // namespace romp::nn::diffmpm
