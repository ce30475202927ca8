// DiffMpm::step: shape, dtype and device checks, then romp::diffmpm's forward and adjoint kernels inside a
// torch::autograd::Function.
#include "nn/diffmpm/mpm_step.h"

#include <string>

#include "kernels/core/error.h"
#include "kernels/diffmpm/dense_grid.h"
#include "kernels/diffmpm/diff_step.h"
#include "nn/tensor_bridge.h"

namespace romp::nn::diffmpm {
namespace {

using torch::autograd::AutogradContext;
using torch::autograd::variable_list;

// The config travels with the autograd node, so a backward pass never depends on the DiffMpm that
// made the forward one.
struct ConfigCapsule : torch::CustomClassHolder {
  explicit ConfigCapsule(const DiffMpmConfig& config) : config(config) {}
  DiffMpmConfig config;
};

template <class T>
romp::diffmpm::StepParams<T> step_params(const DiffMpmConfig& config) {
  romp::diffmpm::StepParams<T> params;
  const mpm::DomainConfig<T> scalars = config.converted<T>();
  params.dt = scalars.fixed_dt;
  params.dx = scalars.dx;
  params.gravity = scalars.gravity;
  params.domain = config.domain();
  return params;
}

void check_planes(const torch::Tensor& tensor, int64_t planes, const torch::Tensor& mass, const std::string& name) {
  ROMP_CHECK(tensor.defined(), name + ": tensor is undefined");
  ROMP_CHECK(tensor.dim() == 2 && tensor.size(0) == planes && tensor.size(1) == mass.size(0),
             name + ": expected shape [" + std::to_string(planes) + ", " + std::to_string(mass.size(0)) + "], got " +
                 c10::str(tensor.sizes()));
  ROMP_CHECK(tensor.scalar_type() == mass.scalar_type() && tensor.device() == mass.device(),
             name + ": " + c10::str(tensor.scalar_type(), " on ", tensor.device()) + ", but the particles' mass is " +
                 c10::str(mass.scalar_type(), " on ", mass.device()));
}

template <class T>
Vec3Planes<T> vectors(const torch::Tensor& tensor, const Exec& exec, const std::string& name) {
  return {as_span<T>(tensor, exec, name).data(), tensor.size(1)};
}
template <class T>
Mat3Planes<T> matrices(const torch::Tensor& tensor, const Exec& exec, const std::string& name) {
  return {as_span<T>(tensor, exec, name).data(), tensor.size(1)};
}

// Kernel views of the step's inputs: x, v, C, F, P, mass, volume (contiguous, checked).
template <class T>
romp::diffmpm::ParticleInputs<T> particle_inputs(const variable_list& in, const Exec& exec) {
  return {in[5].size(0),
          vectors<const T>(in[0], exec, "x"),
          vectors<const T>(in[1], exec, "v"),
          matrices<const T>(in[2], exec, "C"),
          matrices<const T>(in[3], exec, "F"),
          matrices<const T>(in[4], exec, "P"),
          as_span<const T>(in[5], exec, "mass"),
          as_span<const T>(in[6], exec, "volume")};
}

torch::Tensor grid_scratch(const DiffMpmConfig& config, const torch::Tensor& like) {
  return torch::empty({romp::diffmpm::kDenseGridPlanes * romp::diffmpm::dense_grid_nodes(config.domain_cells.data())},
                      like.options());
}

class MpmStepFunction : public torch::autograd::Function<MpmStepFunction> {
 public:
  static variable_list forward(AutogradContext* ctx, const c10::intrusive_ptr<ConfigCapsule>& capsule,
                               const torch::Tensor& x, const torch::Tensor& v, const torch::Tensor& C,
                               const torch::Tensor& F, const torch::Tensor& P, const torch::Tensor& mass,
                               const torch::Tensor& volume) {
    const variable_list in{x.contiguous(), v.contiguous(), C.contiguous(), F.contiguous(),
                           P.contiguous(), mass,           volume};
    const int64_t n = mass.size(0);
    variable_list out{torch::empty({3, n}, x.options()), torch::empty({3, n}, x.options()),
                      torch::empty({9, n}, x.options()), torch::empty({9, n}, x.options())};
    const DiffMpmConfig& config = capsule->config;
    dispatch_real(mass, "DiffMpm: particle mass", [&](auto scalar) {
      using T = decltype(scalar);
      const Exec exec = exec_for(mass);
      torch::Tensor scratch = grid_scratch(config, mass);
      romp::diffmpm::step_forward(
          exec, step_params<T>(config), particle_inputs<T>(in, exec), as_span<T>(scratch, exec, "grid"),
          romp::diffmpm::StateView<T>{vectors<T>(out[0], exec, "x'"), vectors<T>(out[1], exec, "v'"),
                                      matrices<T>(out[2], exec, "C'"), matrices<T>(out[3], exec, "F'")});
    });
    ctx->saved_data["config"] = c10::IValue::make_capsule(capsule);
    ctx->save_for_backward(in);
    return out;
  }

  // Gradients of x', v', C', F' in; gradients of the capsule (none), x, v, C, F, P, mass and volume
  // (constants: none) out.
  static variable_list backward(AutogradContext* ctx, variable_list out_gradients) {
    const variable_list in = ctx->get_saved_variables();
    const DiffMpmConfig& config =
        c10::static_intrusive_pointer_cast<ConfigCapsule>(ctx->saved_data["config"].toCapsule())->config;
    for (torch::Tensor& gradient : out_gradients) gradient = gradient.contiguous();
    const torch::Tensor& mass = in[5];
    const int64_t n = mass.size(0);
    const auto options = mass.options();
    variable_list in_gradients{torch::empty({3, n}, options), torch::empty({3, n}, options),
                               torch::empty({9, n}, options), torch::empty({9, n}, options),
                               torch::empty({9, n}, options)};
    dispatch_real(mass, "DiffMpm: particle mass", [&](auto scalar) {
      using T = decltype(scalar);
      const Exec exec = exec_for(mass);
      torch::Tensor scratch = grid_scratch(config, mass);
      const romp::diffmpm::StateView<const T> out_adjoint{
          vectors<const T>(out_gradients[0], exec, "dL/dx'"), vectors<const T>(out_gradients[1], exec, "dL/dv'"),
          matrices<const T>(out_gradients[2], exec, "dL/dC'"), matrices<const T>(out_gradients[3], exec, "dL/dF'")};
      const romp::diffmpm::InputAdjoints<T> in_adjoint{
          vectors<T>(in_gradients[0], exec, "dL/dx"), vectors<T>(in_gradients[1], exec, "dL/dv"),
          matrices<T>(in_gradients[2], exec, "dL/dC"), matrices<T>(in_gradients[3], exec, "dL/dF"),
          matrices<T>(in_gradients[4], exec, "dL/dP")};
      romp::diffmpm::step_backward(exec, step_params<T>(config), particle_inputs<T>(in, exec),
                                   as_span<T>(scratch, exec, "grid"), out_adjoint, in_adjoint);
    });
    return {torch::Tensor(), in_gradients[0], in_gradients[1], in_gradients[2],
            in_gradients[3], in_gradients[4], torch::Tensor(), torch::Tensor()};
  }
};

}  // namespace

DiffMpm::DiffMpm(const DiffMpmConfig& config, torch::Tensor mass, torch::Tensor volume)
    : config_(config), mass_(mass.contiguous()), volume_(volume.contiguous()) {
  ROMP_CHECK(mass_.dim() == 1, "DiffMpm: mass must be [n], got " + c10::str(mass_.sizes()));
  ROMP_CHECK(volume_.sizes() == mass_.sizes() && volume_.scalar_type() == mass_.scalar_type() &&
                 volume_.device() == mass_.device(),
             "DiffMpm: volume must match mass [n] in dtype and device");
  ROMP_CHECK(config.fixed_dt > 0.0 && config.dx > 0.0, "DiffMpm: fixed_dt and dx must be positive");
  // The wall rule's adjoint is a mask, which Coulomb friction is not (mpm::wall_keep_mask).
  ROMP_CHECK(config.wall_friction == 0.0, "DiffMpm: the walls are frictionless, wall_friction must be 0");
  for (int a = 0; a < 3; ++a)
    ROMP_CHECK(config.domain_cells[a] > 2, "DiffMpm: the domain needs more than 2 cells per axis (margins of 1 cell)");
}

MpmState DiffMpm::step(const MpmState& state, const torch::Tensor& P) const {
  check_planes(state.x, 3, mass_, "x");
  check_planes(state.v, 3, mass_, "v");
  check_planes(state.C, 9, mass_, "C");
  check_planes(state.F, 9, mass_, "F");
  check_planes(P, 9, mass_, "P");
  const variable_list out = MpmStepFunction::apply(c10::make_intrusive<ConfigCapsule>(config_), state.x, state.v,
                                                   state.C, state.F, P, mass_, volume_);
  return {out[0], out[1], out[2], out[3]};
}

}  // namespace romp::nn::diffmpm
