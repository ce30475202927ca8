// rollout(): the substep loop of Ma et al. 2023, Alg. 2, plainly or as checkpointed segments whose graphs are rebuilt
// during backward.
#include "nn/diffmpm/rollout.h"

#include <algorithm>
#include <string>

#include "kernels/core/error.h"

namespace romp::nn::diffmpm {
namespace {

using torch::autograd::AutogradContext;
using torch::autograd::variable_list;

// `steps` substeps with the laws between them; the positions and velocities after each, stacked.
Rollout run_steps(const DiffMpm& sim, MpmState state, const ConstitutiveLaws& laws, int64_t steps) {
  std::vector<torch::Tensor> positions, velocities;
  positions.reserve(size_t(steps));
  velocities.reserve(size_t(steps));
  for (int64_t s = 0; s < steps; ++s) {
    state = sim.step(state, laws.elastic(state.F));
    if (laws.plastic) state.F = laws.plastic(state.F);
    positions.push_back(state.x);
    velocities.push_back(state.v);
  }
  return {torch::stack(positions), torch::stack(velocities), state};
}

// What a checkpointed segment needs to run again in its backward pass.
struct SegmentCapsule : torch::CustomClassHolder {
  SegmentCapsule(const DiffMpm& sim, const ConstitutiveLaws& laws, int64_t steps)
      : sim(sim), laws(laws), steps(steps) {}
  DiffMpm sim;
  ConstitutiveLaws laws;
  int64_t steps;
};

// A segment of substeps whose forward pass keeps no graph (only its input state) and whose backward
// pass rebuilds the graph from that state and differentiates it, as torch.utils.checkpoint does.
// Outputs: positions [steps, 3, n], velocities [steps, 3, n], x, v, C, F.
class SegmentFunction : public torch::autograd::Function<SegmentFunction> {
 public:
  static variable_list forward(AutogradContext* ctx, const c10::intrusive_ptr<SegmentCapsule>& segment,
                               const torch::Tensor& x, const torch::Tensor& v, const torch::Tensor& C,
                               const torch::Tensor& F, torch::TensorList parameters) {
    const Rollout result = run_steps(segment->sim, {x, v, C, F}, segment->laws, segment->steps);
    ctx->saved_data["segment"] = c10::IValue::make_capsule(segment);
    ctx->save_for_backward({x, v, C, F});
    const MpmState& out = result.final_state;
    return {result.positions, result.velocities, out.x, out.v, out.C, out.F};
  }

  static variable_list backward(AutogradContext* ctx, variable_list out_gradients) {
    const auto segment = c10::static_intrusive_pointer_cast<SegmentCapsule>(ctx->saved_data["segment"].toCapsule());
    variable_list state = ctx->get_saved_variables();
    for (torch::Tensor& tensor : state) tensor = tensor.detach().requires_grad_(true);
    // Gradients reach only the parameters that require them; the others get none.
    variable_list wrt = state;
    std::vector<size_t> differentiable;
    const std::vector<torch::Tensor>& parameters = segment->laws.parameters;
    for (size_t i = 0; i < parameters.size(); ++i)
      if (parameters[i].requires_grad()) {
        differentiable.push_back(i);
        wrt.push_back(parameters[i]);
      }

    variable_list outputs;
    {
      torch::AutoGradMode enable_grad(true);
      const Rollout result =
          run_steps(segment->sim, {state[0], state[1], state[2], state[3]}, segment->laws, segment->steps);
      const MpmState& out = result.final_state;
      outputs = {result.positions, result.velocities, out.x, out.v, out.C, out.F};
    }
    const variable_list gradients = torch::autograd::grad(outputs, wrt, out_gradients, /*retain_graph=*/false,
                                                          /*create_graph=*/false, /*allow_unused=*/true);
    variable_list in_gradients(5 + parameters.size());
    for (size_t i = 0; i < 4; ++i) in_gradients[1 + i] = gradients[i];
    for (size_t k = 0; k < differentiable.size(); ++k) in_gradients[5 + differentiable[k]] = gradients[4 + k];
    return in_gradients;
  }
};

}  // namespace

Rollout rollout(const DiffMpm& sim, const MpmState& initial, const ConstitutiveLaws& laws,
                const RolloutOptions& options) {
  ROMP_CHECK(bool(laws.elastic), "rollout: no elastic law");
  ROMP_CHECK(options.steps > 0, "rollout: steps must be positive, got " + std::to_string(options.steps));
  ROMP_CHECK(options.checkpoint_every >= 0,
             "rollout: checkpoint_every must be >= 0, got " + std::to_string(options.checkpoint_every));
  if (options.checkpoint_every == 0) return run_steps(sim, initial, laws, options.steps);

  std::vector<torch::Tensor> positions, velocities;
  MpmState state = initial;
  for (int64_t done = 0; done < options.steps; done += options.checkpoint_every) {
    const int64_t steps = std::min(options.checkpoint_every, options.steps - done);
    const variable_list out = SegmentFunction::apply(c10::make_intrusive<SegmentCapsule>(sim, laws, steps), state.x,
                                                     state.v, state.C, state.F, torch::TensorList(laws.parameters));
    positions.push_back(out[0]);
    velocities.push_back(out[1]);
    state = {out[2], out[3], out[4], out[5]};
  }
  return {torch::cat(positions), torch::cat(velocities), state};
}

}  // namespace romp::nn::diffmpm
