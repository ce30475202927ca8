// Zero-copy views between engine memory and torch::Tensor, checked before any pointer changes hands.
#include "nn/tensor_bridge.h"

#include "kernels/core/error.h"

#if ROMP_TORCH_CUDA
#include <c10/cuda/CUDAStream.h>
#endif

namespace romp::nn {
namespace {

template <class T>
constexpr torch::ScalarType scalar_type() {
  using U = std::remove_const_t<T>;
  if constexpr (std::is_same_v<U, float>)
    return torch::kFloat32;
  else if constexpr (std::is_same_v<U, double>)
    return torch::kFloat64;
  else if constexpr (std::is_same_v<U, std::int32_t>)
    return torch::kInt32;
  else if constexpr (std::is_same_v<U, std::int64_t>)
    return torch::kInt64;
  else
    static_assert(sizeof(U) == 0, "no torch dtype for this element type");
}

}  // namespace

torch::Device torch_device(const Exec& exec) {
  if (exec.is_cuda()) return torch::Device(torch::kCUDA, static_cast<c10::DeviceIndex>(exec.device));
  return torch::Device(torch::kCPU);
}

TorchStreamScope::TorchStreamScope(const Exec& exec) {
  if (!exec.is_cuda()) {
    cpu_access_.emplace();
    return;
  }
#if ROMP_TORCH_CUDA
  const auto device = static_cast<c10::DeviceIndex>(exec.device);
  guard_.emplace(c10::cuda::getStreamFromExternal(exec.stream, device).unwrap());
#else
  throw Error("a CUDA run needs LibTorch with CUDA; this one was built without it");
#endif
}

Exec exec_for(const torch::Tensor& tensor) {
  if (tensor.device().is_cpu()) return Exec::cpu();
  ROMP_CHECK(tensor.device().is_cuda(), "tensor on unsupported device " + tensor.device().str());
#if ROMP_TORCH_CUDA
  const int device = tensor.device().index();
  return Exec::cuda(device, c10::cuda::getCurrentCUDAStream(static_cast<c10::DeviceIndex>(device)).stream());
#else
  throw Error("tensor on " + tensor.device().str() + " but this LibTorch was built without CUDA");
#endif
}

template <class T>
torch::Tensor as_tensor(Span<T> span, const Exec& exec, c10::IntArrayRef shape) {
  const auto elements = c10::multiply_integers(shape);
  ROMP_CHECK(Index(elements) == span.size(), "as_tensor: shape holds " + std::to_string(elements) +
                                                 " elements but the span has " + std::to_string(span.size()));
  const auto options = torch::TensorOptions().dtype(scalar_type<T>()).device(torch_device(exec));
  // from_blob never frees the memory: the engine buffer stays its owner.
  return torch::from_blob(const_cast<std::remove_const_t<T>*>(span.data()), shape, options);
}

template <class T>
Span<T> as_span(const torch::Tensor& tensor, const Exec& exec, const std::string& what) {
  ROMP_CHECK(tensor.defined(), what + ": tensor is undefined");
  ROMP_CHECK(tensor.scalar_type() == scalar_type<T>(), what + ": dtype " +
                                                           std::string(c10::toString(tensor.scalar_type())) +
                                                           ", expected " + c10::toString(scalar_type<T>()));
  ROMP_CHECK(tensor.is_contiguous(), what + ": tensor must be contiguous (call .contiguous() first)");
  ROMP_CHECK(tensor.device() == torch_device(exec),
             what + ": tensor on " + tensor.device().str() + " but the kernel runs on " + torch_device(exec).str());
  return Span<T>(static_cast<T*>(tensor.data_ptr()), Index(tensor.numel()));
}

#define ROMP_BRIDGE_INSTANTIATE(T)                                                         \
  template torch::Tensor as_tensor<T>(Span<T>, const Exec&, c10::IntArrayRef);             \
  template torch::Tensor as_tensor<const T>(Span<const T>, const Exec&, c10::IntArrayRef); \
  template Span<T> as_span<T>(const torch::Tensor&, const Exec&, const std::string&);      \
  template Span<const T> as_span<const T>(const torch::Tensor&, const Exec&, const std::string&);

ROMP_BRIDGE_INSTANTIATE(float)
ROMP_BRIDGE_INSTANTIATE(double)
ROMP_BRIDGE_INSTANTIATE(std::int32_t)
ROMP_BRIDGE_INSTANTIATE(std::int64_t)
#undef ROMP_BRIDGE_INSTANTIATE

}  // namespace romp::nn
