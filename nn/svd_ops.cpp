// torch::Tensor entry points of the batched SVD: shape, dtype and device checks, then the engine's launchers on the
// tensors' memory.
#include "nn/svd_ops.h"

#include <string>

#include "kernels/core/error.h"
#include "kernels/svd/svd3_batched.h"
#include "nn/tensor_bridge.h"

namespace romp::nn {
namespace {

constexpr int64_t kMatrixPlanes = 9;
constexpr int64_t kVectorPlanes = 3;

std::string shape_of(const torch::Tensor& tensor) {
  std::string text = "[";
  for (int64_t d = 0; d < tensor.dim(); ++d) text += (d ? ", " : "") + std::to_string(tensor.size(d));
  return text + "]";
}

void check_shape(const torch::Tensor& tensor, int64_t planes, int64_t count, const std::string& name) {
  ROMP_CHECK(tensor.defined(), name + ": tensor is undefined");
  ROMP_CHECK(tensor.dim() == 2 && tensor.size(0) == planes && tensor.size(1) == count,
             name + ": expected shape [" + std::to_string(planes) + ", " + std::to_string(count) + "] (" +
                 std::to_string(planes) + " planes of n = " + std::to_string(count) + "), got " + shape_of(tensor));
}

// The number of matrices in F [9, n].
int64_t matrix_count(const torch::Tensor& F, const std::string& name) {
  ROMP_CHECK(F.defined(), name + ": tensor is undefined");
  ROMP_CHECK(F.dim() == 2 && F.size(0) == kMatrixPlanes,
             name + ": expected shape [9, n] (one plane per matrix entry), got " + shape_of(F));
  return F.size(1);
}

// Views of the tensors' memory; as_span checks dtype, contiguity and device.
template <class T>
Mat3Planes<T> matrices(const torch::Tensor& tensor, const Exec& exec, int64_t count, const std::string& name) {
  check_shape(tensor, kMatrixPlanes, count, name);
  return {as_span<T>(tensor, exec, name).data(), count};
}
template <class T>
Vec3Planes<T> vectors(const torch::Tensor& tensor, const Exec& exec, int64_t count, const std::string& name) {
  check_shape(tensor, kVectorPlanes, count, name);
  return {as_span<T>(tensor, exec, name).data(), count};
}

// A zero tensor in place of an undefined gradient (left undefined when `like` is, so that the shape
// check names the missing argument).
torch::Tensor or_zeros(const torch::Tensor& gradient, const torch::Tensor& like) {
  return gradient.defined() || !like.defined() ? gradient : torch::zeros_like(like);
}

}  // namespace

Svd3Tensors svd3(const torch::Tensor& F) {
  const int64_t n = matrix_count(F, "F");
  Svd3Tensors out{torch::empty({kMatrixPlanes, n}, F.options()), torch::empty({kVectorPlanes, n}, F.options()),
                  torch::empty({kMatrixPlanes, n}, F.options())};
  svd3_out(F, out.U, out.S, out.V);
  return out;
}

void svd3_out(const torch::Tensor& F, const torch::Tensor& U, const torch::Tensor& S, const torch::Tensor& V) {
  dispatch_real(F, "F", [&](auto scalar) {
    using T = decltype(scalar);
    const Exec exec = exec_for(F);
    const int64_t n = matrix_count(F, "F");
    svd3_batched(exec, matrices<const T>(F, exec, n, "F"), matrices<T>(U, exec, n, "U"), vectors<T>(S, exec, n, "S"),
                 matrices<T>(V, exec, n, "V"));
  });
}

Polar3Tensors polar3(const torch::Tensor& F) {
  const int64_t n = matrix_count(F, "F");
  Polar3Tensors out{torch::empty({kMatrixPlanes, n}, F.options()), torch::empty({kMatrixPlanes, n}, F.options())};
  polar3_out(F, out.R, out.S);
  return out;
}

void polar3_out(const torch::Tensor& F, const torch::Tensor& R, const torch::Tensor& S) {
  dispatch_real(F, "F", [&](auto scalar) {
    using T = decltype(scalar);
    const Exec exec = exec_for(F);
    const int64_t n = matrix_count(F, "F");
    polar3_batched(exec, matrices<const T>(F, exec, n, "F"), matrices<T>(R, exec, n, "R"),
                   matrices<T>(S, exec, n, "S"));
  });
}

torch::Tensor svd3_backward(const torch::Tensor& U, const torch::Tensor& S, const torch::Tensor& V,
                            const torch::Tensor& dU, const torch::Tensor& dS, const torch::Tensor& dV) {
  const int64_t n = matrix_count(U, "U");
  torch::Tensor dF = torch::empty({kMatrixPlanes, n}, U.options());
  const torch::Tensor gradient_U = or_zeros(dU, U), gradient_S = or_zeros(dS, S), gradient_V = or_zeros(dV, V);
  dispatch_real(U, "U", [&](auto scalar) {
    using T = decltype(scalar);
    const Exec exec = exec_for(U);
    svd3_backward_batched(exec, matrices<const T>(U, exec, n, "U"), vectors<const T>(S, exec, n, "S"),
                          matrices<const T>(V, exec, n, "V"), matrices<const T>(gradient_U, exec, n, "dU"),
                          vectors<const T>(gradient_S, exec, n, "dS"), matrices<const T>(gradient_V, exec, n, "dV"),
                          matrices<T>(dF, exec, n, "dF"));
  });
  return dF;
}

torch::Tensor polar3_backward(const torch::Tensor& F, const torch::Tensor& dR, const torch::Tensor& dS) {
  const int64_t n = matrix_count(F, "F");
  torch::Tensor dF = torch::empty({kMatrixPlanes, n}, F.options());
  const torch::Tensor gradient_R = or_zeros(dR, F), gradient_S = or_zeros(dS, F);
  dispatch_real(F, "F", [&](auto scalar) {
    using T = decltype(scalar);
    const Exec exec = exec_for(F);
    polar3_backward_batched(exec, matrices<const T>(F, exec, n, "F"), matrices<const T>(gradient_R, exec, n, "dR"),
                            matrices<const T>(gradient_S, exec, n, "dS"), matrices<T>(dF, exec, n, "dF"));
  });
  return dF;
}

}  // namespace romp::nn
