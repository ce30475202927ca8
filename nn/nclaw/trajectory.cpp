// Trajectory: shape, dtype and device checks, conversion, and simulation under a known law.
#include "nn/nclaw/trajectory.h"

#include <string>

#include "kernels/core/error.h"

namespace romp::nn::nclaw {

void Trajectory::validate() const {
  ROMP_CHECK(mass.defined() && mass.dim() == 1 && mass.size(0) > 0, "trajectory: mass must be [n] with n > 0");
  const int64_t n = mass.size(0);
  ROMP_CHECK(x.defined() && x.dim() == 3 && x.size(0) >= 2,
             "trajectory: x must be [frames, 3, n] with at least 2 frames");
  const int64_t frames = x.size(0);
  const auto expect = [&](const torch::Tensor& tensor, std::vector<int64_t> shape, const char* name) {
    ROMP_CHECK(tensor.defined() && tensor.sizes() == c10::IntArrayRef(shape),
               std::string("trajectory: ") + name + " must be " + c10::str(c10::IntArrayRef(shape)) + ", got " +
                   (tensor.defined() ? c10::str(tensor.sizes()) : std::string("nothing")));
    ROMP_CHECK(tensor.scalar_type() == mass.scalar_type() && tensor.device() == mass.device(),
               std::string("trajectory: ") + name + " is " + c10::str(tensor.scalar_type(), " on ", tensor.device()) +
                   ", mass " + c10::str(mass.scalar_type(), " on ", mass.device()));
  };
  expect(volume, {n}, "volume");
  expect(x, {frames, 3, n}, "x");
  expect(v, {frames, 3, n}, "v");
  expect(C, {frames, 9, n}, "C");
  expect(F, {frames, 9, n}, "F");
}

void Trajectory::require_steps(int64_t steps, const std::string& who) const {
  ROMP_CHECK(frame_count() > steps, who + ": " + std::to_string(steps) + " substeps need " + std::to_string(steps + 1) +
                                        " ground-truth frames, the trajectory has " + std::to_string(frame_count()));
}

Trajectory Trajectory::to(const torch::Device& device, torch::ScalarType dtype) const {
  const auto convert = [&](const torch::Tensor& t) { return t.to(device, dtype).contiguous(); };
  return {convert(mass), convert(volume), convert(x), convert(v), convert(C), convert(F)};
}

Trajectory simulate(const diffmpm::DiffMpm& sim, const diffmpm::MpmState& initial,
                    const diffmpm::ConstitutiveLaws& laws, int64_t steps) {
  torch::NoGradGuard no_grad;
  std::vector<torch::Tensor> x{initial.x}, v{initial.v}, C{initial.C}, F{initial.F};
  diffmpm::MpmState state = initial;
  for (int64_t s = 0; s < steps; ++s) {
    state = diffmpm::rollout(sim, state, laws, {1, 0}).final_state;
    x.push_back(state.x);
    v.push_back(state.v);
    C.push_back(state.C);
    F.push_back(state.F);
  }
  return {sim.mass(), sim.volume(), torch::stack(x), torch::stack(v), torch::stack(C), torch::stack(F)};
}

}  // namespace romp::nn::nclaw
