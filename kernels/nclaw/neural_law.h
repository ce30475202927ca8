// Batched neural constitutive laws over the engine's planes: the fused forward pass, its backward pass and
// the weight gradients, on either backend (the CPU run is the reference the CUDA run must match).
//
// On CUDA one thread per particle runs the whole law (law_network.h); the host runs blocks of 16 particles
// one per SIMD lane (law_lanes.h), its reference. The weight gradients are sums over the particles'
// activation rows. A training substep is thus three launches per law where LibTorch took ~40, and a
// full-order substep one per neural material and stage.
#pragma once

#include <cstdint>

#include "kernels/core/exec.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/nclaw/law_network.h"

namespace romp::nclaw {

// The particles a law applies to: every one, or those of one material, optionally only those outside
// Dirichlet groups (the rule of mpm::project_plasticity). Others' outputs are left as they were.
struct LawSelection {
  const std::int32_t* material = nullptr;  // null: every particle
  std::int32_t material_id = 0;
  const std::int32_t* dirichlet_group = nullptr;  // not null: only particles in mpm::kNoDirichletGroup
};

// Y = the law at F for the selected particles. Y may be F itself (the plastic law in place).
template <class T>
void law_forward(const Exec& exec, const LawWeights<T>& weights, const LawOutput<T>& output, Mat3Planes<const T> F,
                 Mat3Planes<T> Y, const LawSelection& selection = {});

// For every particle: dF = dL/dF from dY = dL/dY, and the weight gradients dW (row-major, as the weights)
// summed over the particles in order. `activations` holds kLawActivationPlanes × count scalars.
template <class T>
struct LawGradients {
  Mat3Planes<T> F;
  T* input = nullptr;   // [64, 13]
  T* hidden = nullptr;  // [64, 64]
  T* output = nullptr;  // [9, 64]
};
template <class T>
void law_backward(const Exec& exec, const LawWeights<T>& weights, const LawOutput<T>& output, Mat3Planes<const T> F,
                  Mat3Planes<const T> dY, Span<T> activations, const LawGradients<T>& gradients);

}  // namespace romp::nclaw
