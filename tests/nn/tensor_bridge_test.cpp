// The tensor bridge shares memory both ways and refuses tensors a kernel could misread.
#include <gtest/gtest.h>

#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/error.h"
#include "nn/tensor_bridge.h"

namespace romp::nn {
namespace {

TEST(TensorBridge, TensorAliasesEngineMemory) {
  DeviceBuffer<float> buffer = DeviceBuffer<float>::from_host(Backend::Cpu, std::vector<float>(6, 1.0f));
  torch::Tensor tensor = as_tensor(buffer.span(), Exec::cpu(), {2, 3});
  EXPECT_EQ(tensor.data_ptr<float>(), buffer.data());
  EXPECT_EQ(tensor.sizes(), (std::vector<int64_t>{2, 3}));
  tensor.mul_(4.0f);
  EXPECT_EQ(buffer.to_host(), std::vector<float>(6, 4.0f));
}

TEST(TensorBridge, SpanAliasesTensorMemory) {
  torch::Tensor tensor = torch::zeros({3, 4}, torch::kFloat64);
  const Span<double> span = as_span<double>(tensor, exec_for(tensor), "F");
  EXPECT_EQ(span.size(), 12);
  span[5] = 2.5;
  EXPECT_EQ(tensor[1][1].item<double>(), 2.5);
}

TEST(TensorBridge, ShapeMustHoldTheSpan) {
  DeviceBuffer<float> buffer(Backend::Cpu, 5);
  EXPECT_THROW(as_tensor(buffer.span(), Exec::cpu(), {2, 3}), Error);
}

TEST(TensorBridge, WrongDtypeIsNamedInTheError) {
  const torch::Tensor tensor = torch::zeros({4}, torch::kFloat64);
  try {
    as_span<float>(tensor, Exec::cpu(), "stress");
    FAIL() << "a float64 tensor was accepted as float32";
  } catch (const Error& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("stress"), std::string::npos);
    EXPECT_NE(what.find("Double"), std::string::npos);
  }
}

TEST(TensorBridge, NonContiguousTensorIsRefused) {
  const torch::Tensor tensor = torch::zeros({4, 3}, torch::kFloat32).t();
  EXPECT_THROW(as_span<float>(tensor, Exec::cpu(), "F"), Error);
}

TEST(TensorBridge, DeviceMismatchIsRefused) {
  const torch::Tensor tensor = torch::zeros({4}, torch::kFloat32);
  EXPECT_THROW(as_span<float>(tensor, Exec::cuda(), "F"), Error);
}

}  // namespace
}  // namespace romp::nn
