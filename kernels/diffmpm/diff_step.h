// The differentiable MLS-MPM substep on a dense grid: forward (P2G, grid update, G2P) and its adjoint.
//
// One substep of Ma et al. 2023, Alg. 3 (MLS-MPM with APIC, Hu et al. 2018) with the stress as an
// input: I(x, v, C, F, P) = (x', v', C', F_trial'). The first Piola stress P comes from outside (a
// LibTorch law evaluated before the step) and the plastic projection of F_trial' is applied after it,
// so the same kernels serve every constitutive law, neural or analytic, and autograd connects them.
// step_backward maps ∂L/∂(x', v', C', F') to ∂L/∂(x, v, C, F, P) with hand-written adjoint kernels,
// in reverse order: G2P adjoint, grid-update adjoint, P2G adjoint. Where a forward kernel scatters
// (P2G) its adjoint gathers, and where the forward gathers (G2P) the adjoint scatters with atomics.
// The grid is not stored between the passes: step_backward recomputes it from the step's inputs
// (one P2G and grid update), so a rollout keeps only particle states per step.
#pragma once

#include "kernels/core/exec.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/math/vec3.h"
#include "kernels/mpm/domain_walls.h"

namespace romp::diffmpm {

template <class T>
struct StepParams {
  T dt = T(0);
  T dx = T(0);
  Vec3<T> gravity = Vec3<T>::zero();
  // The box, its dense grid (cells + 1 nodes per axis) and its walls, whose frictionless rule is the
  // engine's (mpm::wall_keep_mask): Separate is the free-slip wall of the authors' code.
  mpm::Domain domain;
};

// The inputs of a step, n particles in the engine's planes. mass and volume are constants.
template <class T>
struct ParticleInputs {
  Index count = 0;
  Vec3Planes<const T> x, v;
  Mat3Planes<const T> C, F, P;  // P: first Piola–Kirchhoff stress at F
  Span<const T> mass, volume;   // kg, reference volume m³
};

// A step's outputs (x', v', C', F_trial'), or their adjoints.
template <class T>
struct StateView {
  Vec3Planes<T> x, v;
  Mat3Planes<T> C, F;
};

// ∂L/∂ of a step's differentiable inputs.
template <class T>
struct InputAdjoints {
  Vec3Planes<T> x, v;
  Mat3Planes<T> C, F, P;
};

// Both launchers need scratch of kDenseGridPlanes × dense_grid_nodes(params.domain.cells) scalars (see
// dense_grid.h) on exec's backend. Outputs must not alias inputs. Instantiated for float and double.
template <class T>
void step_forward(const Exec& exec, const StepParams<T>& params, const ParticleInputs<T>& in, Span<T> scratch,
                  const StateView<T>& out);
template <class T>
void step_backward(const Exec& exec, const StepParams<T>& params, const ParticleInputs<T>& in, Span<T> scratch,
                   const StateView<const T>& out_adjoint, const InputAdjoints<T>& in_adjoint);

// P2G and the grid update alone, into the scratch grid (what both launchers start with).
template <class T>
void grid_forward(const Exec& exec, const StepParams<T>& params, const ParticleInputs<T>& in, Span<T> scratch);

}  // namespace romp::diffmpm
