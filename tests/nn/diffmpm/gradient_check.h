// Central finite differences of a scalar loss over every entry of a float64 tensor, for gradient checks.
#pragma once

#include <torch/torch.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace romp::nn::test {

// max |gradient − central difference| / max |central difference| over the entries 0, stride,
// 2 stride, … of `tensor` (float64, contiguous, CPU), each perturbed in place by
// h = relative_step · max(1, |entry|) and restored.
inline double finite_difference_error(const torch::Tensor& tensor, const torch::Tensor& gradient,
                                      const std::function<double()>& loss, double relative_step = 1e-6,
                                      int64_t stride = 1) {
  torch::NoGradGuard no_grad;
  double* values = tensor.data_ptr<double>();
  const torch::Tensor expected = gradient.contiguous();
  const double* analytic = expected.data_ptr<double>();
  double largest_error = 0.0, largest = 0.0;
  for (int64_t i = 0; i < tensor.numel(); i += stride) {
    const double original = values[i];
    const double h = relative_step * std::max(1.0, std::abs(original));
    values[i] = original + h;
    const double plus = loss();
    values[i] = original - h;
    const double minus = loss();
    values[i] = original;
    const double difference = (plus - minus) / (2.0 * h);
    largest_error = std::max(largest_error, std::abs(difference - analytic[i]));
    largest = std::max(largest, std::abs(difference));
  }
  return largest_error / largest;
}

}  // namespace romp::nn::test
