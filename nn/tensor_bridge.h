// Zero-copy bridge between engine memory (Span, DeviceBuffer) and torch::Tensor, with guards.
#pragma once

#include <torch/torch.h>

#include <optional>
#include <string>

#include <c10/core/StreamGuard.h>

#include "kernels/core/error.h"
#include "kernels/core/exec.h"
#include "kernels/core/guarded_memory.h"
#include "kernels/core/span.h"

namespace romp::nn {

// The torch device that corresponds to `exec` (kCPU, or kCUDA with exec.device).
torch::Device torch_device(const Exec& exec);

// The Exec a tensor's data lives on; on CUDA it uses PyTorch's current stream for that device, so
// romp kernels and LibTorch ops on the same tensors stay ordered.
Exec exec_for(const torch::Tensor& tensor);

// While alive, LibTorch queues its work for `exec`'s CUDA device on exec.stream, so torch ops on
// tensors that alias engine memory run in order with romp's kernels on that stream, with no
// synchronisation. On the CPU those ops are the device's work: they may touch guarded memory
// (kernels/core/guarded_memory.h).
class TorchStreamScope {
 public:
  explicit TorchStreamScope(const Exec& exec);

 private:
  std::optional<c10::StreamGuard> guard_;
  std::optional<memory::DeviceAccess> cpu_access_;
};

// A tensor of `shape` that aliases `span` (no copy). The span must outlive the tensor.
template <class T>
torch::Tensor as_tensor(Span<T> span, const Exec& exec, c10::IntArrayRef shape);

// A view of a tensor's elements (no copy). Checks, and names `what` in the error if one fails:
// dtype is T, the tensor is contiguous and on `exec`'s device.
template <class T>
Span<T> as_span(const torch::Tensor& tensor, const Exec& exec, const std::string& what);

// Calls work(T{}) with T the C++ type of `tensor`'s dtype, float or double; any other dtype (or an
// undefined tensor) is a romp::Error that names `what`.
template <class Work>
void dispatch_real(const torch::Tensor& tensor, const std::string& what, const Work& work) {
  if (tensor.defined() && tensor.scalar_type() == torch::kFloat32) {
    work(float{});
  } else if (tensor.defined() && tensor.scalar_type() == torch::kFloat64) {
    work(double{});
  } else {
    throw Error(
        what + ": " +
        (tensor.defined() ? "dtype " + std::string(c10::toString(tensor.scalar_type())) : std::string("undefined")) +
        ", expected float32 or float64");
  }
}

}  // namespace romp::nn
