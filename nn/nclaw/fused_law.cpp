// fused_law(): checks, then romp::nclaw::law_forward / law_backward inside a torch::autograd::Function.
#include "nn/nclaw/fused_law.h"

#include <string>

#include "kernels/core/error.h"
#include "kernels/nclaw/neural_law.h"
#include "nn/tensor_bridge.h"

namespace romp::nn::nclaw {
namespace {

using torch::autograd::AutogradContext;
using torch::autograd::variable_list;

template <class T>
romp::nclaw::LawWeights<T> weights_of(const torch::Tensor& input, const torch::Tensor& hidden,
                                      const torch::Tensor& output, const Exec& exec) {
  return {as_span<const T>(input, exec, "law input weight").data(),
          as_span<const T>(hidden, exec, "law hidden weight").data(),
          as_span<const T>(output, exec, "law output weight").data()};
}

template <class T>
Mat3Planes<T> planes_of(const torch::Tensor& tensor, const Exec& exec, const std::string& what) {
  return {as_span<T>(tensor, exec, what).data(), tensor.size(1)};
}

class FusedLawFunction : public torch::autograd::Function<FusedLawFunction> {
 public:
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& deformation,
                               const torch::Tensor& input_weight, const torch::Tensor& hidden_weight,
                               const torch::Tensor& output_weight, double scale, bool adds_input) {
    const torch::Tensor F = deformation.contiguous(), input = input_weight.contiguous(),
                        hidden = hidden_weight.contiguous(), output = output_weight.contiguous();
    torch::Tensor Y = torch::empty_like(F);
    dispatch_real(F, "neural law: F", [&](auto scalar) {
      using T = decltype(scalar);
      const Exec exec = exec_for(F);
      romp::nclaw::law_forward<T>(exec, weights_of<T>(input, hidden, output, exec), {T(scale), adds_input},
                                  planes_of<const T>(F, exec, "neural law F"), planes_of<T>(Y, exec, "neural law Y"));
    });
    ctx->save_for_backward({F, input, hidden, output});
    ctx->saved_data["scale"] = scale;
    ctx->saved_data["adds_input"] = adds_input;
    return Y;
  }

  // Gradients of F and the three weights; none for scale and adds_input.
  static variable_list backward(AutogradContext* ctx, variable_list gradients) {
    const variable_list saved = ctx->get_saved_variables();
    const torch::Tensor &F = saved[0], &input = saved[1], &hidden = saved[2], &output = saved[3];
    const double scale = ctx->saved_data["scale"].toDouble();
    const bool adds_input = ctx->saved_data["adds_input"].toBool();
    const torch::Tensor dY = gradients[0].contiguous();
    torch::Tensor dF = torch::empty_like(F), d_input = torch::empty_like(input), d_hidden = torch::empty_like(hidden),
                  d_output = torch::empty_like(output);
    torch::Tensor activations = torch::empty({romp::nclaw::kLawActivationPlanes * F.size(1)}, F.options());
    dispatch_real(F, "neural law: F", [&](auto scalar) {
      using T = decltype(scalar);
      const Exec exec = exec_for(F);
      const romp::nclaw::LawGradients<T> out{planes_of<T>(dF, exec, "neural law dF"),
                                             as_span<T>(d_input, exec, "law input weight gradient").data(),
                                             as_span<T>(d_hidden, exec, "law hidden weight gradient").data(),
                                             as_span<T>(d_output, exec, "law output weight gradient").data()};
      romp::nclaw::law_backward<T>(exec, weights_of<T>(input, hidden, output, exec), {T(scale), adds_input},
                                   planes_of<const T>(F, exec, "neural law F"),
                                   planes_of<const T>(dY, exec, "neural law dY"),
                                   as_span<T>(activations, exec, "neural law activations"), out);
    });
    return {dF, d_input, d_hidden, d_output, torch::Tensor(), torch::Tensor()};
  }
};

void check_weight(const torch::Tensor& weight, int64_t outputs, int64_t inputs, const torch::Tensor& F,
                  const std::string& name) {
  ROMP_CHECK(weight.defined() && weight.dim() == 2 && weight.size(0) == outputs && weight.size(1) == inputs,
             "neural law: " + name + " weight must be [" + std::to_string(outputs) + ", " + std::to_string(inputs) +
                 "], got " + (weight.defined() ? c10::str(weight.sizes()) : std::string("undefined")));
  ROMP_CHECK(weight.scalar_type() == F.scalar_type() && weight.device() == F.device(),
             "neural law: " + name + " weight is " + c10::str(weight.scalar_type(), " on ", weight.device()) +
                 ", F is " + c10::str(F.scalar_type(), " on ", F.device()));
}

}  // namespace

torch::Tensor fused_law(const torch::Tensor& F, const LawParameters& parameters, double scale, bool adds_input) {
  ROMP_CHECK(F.defined() && F.dim() == 2 && F.size(0) == 9,
             "neural law: F must be [9, n], got " + (F.defined() ? c10::str(F.sizes()) : std::string("undefined")));
  check_weight(parameters.input, romp::nclaw::kLawWidth, romp::nclaw::kLawInputs, F, "input");
  check_weight(parameters.hidden, romp::nclaw::kLawWidth, romp::nclaw::kLawWidth, F, "hidden");
  check_weight(parameters.output, romp::nclaw::kLawOutputs, romp::nclaw::kLawWidth, F, "output");
  return FusedLawFunction::apply(F, parameters.input, parameters.hidden, parameters.output, scale, adds_input);
}

}  // namespace romp::nn::nclaw
