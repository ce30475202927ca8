// Adam (Kingma and Ba, with PyTorch's defaults and update order) whose step count and moments are plain tensors,
// so a training checkpoint stores them in HDF5 and a resumed run continues bitwise. (torch::optim::Adam keys its
// state by tensor address, differently in each LibTorch version romp builds against.)
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <vector>

namespace romp::nn::rom {

class Adam {
 public:
  static constexpr double kBeta1 = 0.9, kBeta2 = 0.999, kEpsilon = 1e-8;

  explicit Adam(std::vector<torch::Tensor> parameters);

  // One update of every parameter from its gradient (a parameter without one is left alone); then the
  // gradients are zeroed.
  void step(double learning_rate);

  std::int64_t steps() const { return steps_; }
  const std::vector<torch::Tensor>& parameters() const { return parameters_; }
  const std::vector<torch::Tensor>& first_moments() const { return first_; }
  const std::vector<torch::Tensor>& second_moments() const { return second_; }
  // Continues from a stored state: the moments must match the parameters in number, shape and device.
  void restore(std::int64_t steps, const std::vector<torch::Tensor>& first, const std::vector<torch::Tensor>& second);

 private:
  std::vector<torch::Tensor> parameters_, first_, second_;
  std::int64_t steps_ = 0;
};

}  // namespace romp::nn::rom
