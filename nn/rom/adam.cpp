// Adam's update, as torch.optim.Adam computes it (bias corrections folded into the step size and denominator).
#include "nn/rom/adam.h"

#include <cmath>
#include <string>

#include "kernels/core/error.h"

namespace romp::nn::rom {

Adam::Adam(std::vector<torch::Tensor> parameters) : parameters_(std::move(parameters)) {
  for (const torch::Tensor& p : parameters_) {
    first_.push_back(torch::zeros_like(p));
    second_.push_back(torch::zeros_like(p));
  }
}

void Adam::step(double learning_rate) {
  torch::NoGradGuard no_grad;
  ++steps_;
  const double correction1 = 1.0 - std::pow(kBeta1, double(steps_));
  const double correction2 = 1.0 - std::pow(kBeta2, double(steps_));
  for (std::size_t i = 0; i < parameters_.size(); ++i) {
    torch::Tensor& p = parameters_[i];
    if (!p.grad().defined()) continue;
    const torch::Tensor g = p.grad();
    first_[i].mul_(kBeta1).add_(g, 1.0 - kBeta1);
    second_[i].mul_(kBeta2).addcmul_(g, g, 1.0 - kBeta2);
    const torch::Tensor denominator = (second_[i].sqrt() / std::sqrt(correction2)).add_(kEpsilon);
    p.addcdiv_(first_[i], denominator, -learning_rate / correction1);
    p.mutable_grad().zero_();
  }
}

void Adam::restore(std::int64_t steps, const std::vector<torch::Tensor>& first,
                   const std::vector<torch::Tensor>& second) {
  ROMP_CHECK(steps >= 0, "Adam: negative step count");
  ROMP_CHECK(first.size() == parameters_.size() && second.size() == parameters_.size(),
             "Adam: " + std::to_string(first.size()) + " stored moments for " + std::to_string(parameters_.size()) +
                 " parameters");
  for (std::size_t i = 0; i < parameters_.size(); ++i) {
    ROMP_CHECK(first[i].sizes() == parameters_[i].sizes() && second[i].sizes() == parameters_[i].sizes(),
               "Adam: stored moments of parameter " + std::to_string(i) + " have another shape");
    first_[i] = first[i].to(parameters_[i].options()).clone();
    second_[i] = second[i].to(parameters_[i].options()).clone();
  }
  steps_ = steps;
}

}  // namespace romp::nn::rom
