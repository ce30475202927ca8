// law suite: one neural constitutive law (Ma et al. 2023, 13 → 64 → 64 → 9 GELU) on 1k particles (a training
// substep's) and 117,602 (the pool scene's), forward alone and forward + backward: romp's fused kernels
// against the same law composed of LibTorch operators, the same weights and F on the same device.
#include <fmt/format.h>
#include <torch/torch.h>

#include <string>

#include "bench/suites/suites.h"
#include "nn/nclaw/composed_law.h"
#include "nn/nclaw/fused_law.h"
#include "nn/nclaw/neural_laws.h"
#include "nn/tensor_bridge.h"

namespace romp::bench {

void run_law_suite(Context& context) {
  for (const Index nominal : {Index(1000), Index(117602)}) {
    const Index n = context.scaled(nominal, 100);
    for (const Exec& exec : context.execs()) {
      if (exec.is_cuda() && !torch::cuda::is_available()) {
        fmt::print("law: skipped on cuda, this LibTorch has no CUDA device\n");
        continue;
      }
      // LibTorch's ops on exec's stream (CUDA) and threads (CPU), as the fused kernels.
      const nn::TorchStreamScope stream(exec);
      const int torch_threads = torch::get_num_threads();
      if (!exec.is_cuda()) torch::set_num_threads(exec.threads);
      const torch::TensorOptions options = torch::TensorOptions().device(nn::torch_device(exec));
      torch::manual_seed(0);
      nn::nclaw::ElasticLaw law;
      law->to(options.device());
      const nn::nclaw::LawParameters& w = law->weights();
      const torch::Tensor F =
          (torch::eye(3, options).reshape({9, 1}) + 0.2 * torch::randn({9, n}, options)).requires_grad_(true);
      const torch::Tensor upstream = torch::randn({9, n}, options);

      const std::string size = nominal >= 100000 ? "pool" : "1k";
      const auto forward = [&](auto law_function) {
        torch::NoGradGuard no_gradients;
        law_function(F, w, 1.0, false);
      };
      const auto both = [&](auto law_function) { (law_function(F, w, 1.0, false) * upstream).sum().backward(); };
      const auto fused = [](const torch::Tensor& f, const nn::nclaw::LawParameters& p, double s, bool a) {
        return nn::nclaw::fused_law(f, p, s, a);
      };
      const auto composed = [](const torch::Tensor& f, const nn::nclaw::LawParameters& p, double s, bool a) {
        return nn::nclaw::composed_law(f, p, s, a);
      };
      // context.time returns a reference into a vector that the next measurement may move: keep copies.
      const Measurement fused_forward = context.time(
          "law", "fused_forward_" + size, exec, n, "particle", [&] { forward(fused); }, 0.0,
          "elastic law, fused kernel");
      const Measurement composed_forward = context.time(
          "law", "composed_forward_" + size, exec, n, "particle", [&] { forward(composed); }, 0.0,
          "the same law op by op (LibTorch)");
      const Measurement fused_both = context.time(
          "law", "fused_forward_backward_" + size, exec, n, "particle", [&] { both(fused); }, 0.0,
          "forward and backward (gradients of F and the weights), fused kernels");
      const Measurement composed_both = context.time(
          "law", "composed_forward_backward_" + size, exec, n, "particle", [&] { both(composed); }, 0.0,
          "the same op by op (LibTorch autograd)");
      torch::set_num_threads(torch_threads);
      const std::string key = fmt::format("law.{}.{}{}", size, fused_forward.backend, fused_forward.threads);
      context.record(key + ".forward_speedup", composed_forward.median_seconds() / fused_forward.median_seconds());
      context.record(key + ".forward_backward_speedup", composed_both.median_seconds() / fused_both.median_seconds());
    }
  }
}

}  // namespace romp::bench
